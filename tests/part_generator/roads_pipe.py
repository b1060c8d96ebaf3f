"""A second generator of roads side by side and of a bead along a pipe,
written from docs/data-formats.md alone (not from libbead/sim), written as
another tool would (the long-form part CSV and a rig file), with the truth
beside it.

It differs from the twin (sim/part_twin.h) where a generator can:
  - the road's cross-section is a wire-arc bead's: a cosine cap (the sine
    model of WAAM's bead profiles) or a parabola, neither a superellipse;
  - material is kept: a road laid over the flank of the one before keeps
    its shape and grows (wider and taller alike, its foot on the bed) until
    what it adds over the surface before it is the material the torch laid;
    a road's material swings along the path and each road wanders off its
    line;
  - on a pipe the bead drapes over the curve: its gain over the pipe is the
    cap whatever the slope, and it wanders up to the given distance off the
    crest; the pipe's crest is not under the sensor's middle;
  - each sensor point is the surface averaged over the laser spot, with
    noise and dropouts.

Units: mm, s. Run: python3 roads_pipe.py roads OUT_DIR [--ratio 0.85] or
python3 roads_pipe.py pipe OUT_DIR [--radius-mm 40 --wander-mm 3]."""
import argparse
import math
import os

import numpy as np

from tamped_wall import spot_average


class Config:
    roads = 4
    width_mm = 6.0  # a lone road's foot on the bed, mean
    aspect = 0.45  # its height over its half-width
    ratio = 0.85  # the centre spacing over width_mm
    area_wave = 0.08  # the material's relative swing along the path ...
    area_period_mm = 23.0  # ... and its period
    wander_sigma_mm = 0.1  # each road off its line (a wander that returns over ...
    wander_length_mm = 10.0  # ... this length of path)
    length_mm = 60.0
    profile_spacing_mm = 0.5
    points, field_half_mm = 801, 20.0
    spot_mm = 0.05
    noise_mm = 0.01
    dropout = 1.0 / 300.0
    standoff_mm = 60.0
    fine_mm = 0.005
    cap = "cosine"  # or "parabola"
    laid = "left-first"  # or "right-first"
    # The pipe: its radius, how far the bead wanders off the crest, and
    # where the crest lies across the sensor's field.
    radius_mm = 40.0
    wander_mm = 3.0
    crest_x_mm = 1.3
    reference_mm = 5.0  # the rig's reference areas: this wide at each end of the field


def cap(c, u):
    """The cap's rise over its height at u = (x - centre) / half-width (0
    outside |u| < 1), and its area over half-width times height."""
    inside = np.abs(u) < 1
    if c.cap == "parabola":
        return np.where(inside, 1 - u * u, 0.0), 4.0 / 3.0
    return np.where(inside, np.cos(0.5 * math.pi * u), 0.0), 4.0 / math.pi


def grown(c, x, before, centre, area):
    """The road at `centre` laying `area` over the surface `before` (on the
    bed, z = 0): its scale s (half-width s a0, height s h0) by bisection on
    the material it adds; the surface after, the half-width and height."""
    a0 = 0.5 * c.width_mm
    h0 = c.aspect * a0

    def top(s):
        rise, _ = cap(c, (x - centre) / (s * a0))
        return np.where(rise > 0, s * h0 * rise, -np.inf)

    def added(s):
        return np.sum(np.clip(top(s) - before, 0, None)) * (x[1] - x[0])

    lo, hi = 0.2, 0.5
    while added(hi) < area:
        hi *= 1.5
    for _ in range(50):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if added(mid) < area else (lo, mid)
    s = 0.5 * (lo + hi)
    return np.fmax(before, top(s)), s * a0, s * h0


def sensed(c, rng, x_fine, surfaces, frame_z):
    """Each profile's points: the surface averaged over the spot, in the
    sensor's frame (the bed frame less frame_z), with noise and dropouts."""
    x_sensor = np.linspace(-c.field_half_mm, c.field_half_mm, c.points)
    seen = spot_average(x_fine, surfaces, np.repeat(x_sensor[None, :], len(surfaces), axis=0), c.spot_mm)
    z = seen - frame_z + rng.normal(0, c.noise_mm, seen.shape)
    z[rng.random(z.shape) < c.dropout] = np.nan
    return x_sensor, z


def paths(c, rng, count):
    """The profiles' places along the path, the material's swing at each
    (one phase per road) and each road's wander (each step keeps part of
    the one before: a wander that stays within a few sigmas of the line)."""
    p = np.arange(0.0, c.length_mm, c.profile_spacing_mm)
    swing = 1 + c.area_wave * np.sin(2 * math.pi * p[:, None] / c.area_period_mm + rng.uniform(0, 6.3, count))
    keep = math.exp(-c.profile_spacing_mm / c.wander_length_mm)
    kicks = rng.normal(0, c.wander_sigma_mm * math.sqrt(1 - keep * keep), (p.size, count))
    wander = rng.normal(0, c.wander_sigma_mm, (p.size, count))
    for i in range(1, p.size):
        wander[i] = keep * wander[i - 1] + kicks[i]
    return p, swing, wander


def generate_roads(c, seed):
    """Roads laid in order (c.laid: from the left or the right), each over
    the surface the ones before left; the truth's rows left to right."""
    rng = np.random.default_rng(seed)
    p, swing, wander = paths(c, rng, c.roads)
    x_fine = np.arange(-c.field_half_mm - 2, c.field_half_mm + 2, c.fine_mm)
    _, unit = cap(c, np.zeros(1))
    lone = unit * 0.5 * c.width_mm * c.aspect * 0.5 * c.width_mm
    side = 1.0 if c.laid == "left-first" else -1.0
    first = -0.5 * (c.roads - 1) * c.ratio * c.width_mm
    surfaces, truth = np.zeros((p.size, x_fine.size)), []
    for i in range(p.size):
        surface, laid = np.zeros(x_fine.size), []
        for k in range(c.roads):
            centre = side * (first + k * c.ratio * c.width_mm) + wander[i, k]
            area = lone * swing[i, k]
            surface, a, h = grown(c, x_fine, surface, centre, area)
            laid.append((area, centre, 2 * a, h))
        surfaces[i] = surface
        laid.sort(key=lambda road: road[1])
        naive = cut_at_valleys(x_fine, surface, [road[1] for road in laid])
        truth += [(i, k, *road, cut) for k, (road, cut) in enumerate(zip(laid, naive))]
    x_sensor, z = sensed(c, rng, x_fine, surfaces, c.standoff_mm)
    return p, x_sensor, z, truth


def cut_at_valleys(x, surface, centres):
    """What a vertical cut at the lowest point between each two centres
    (left to right) gives each road (the naive split)."""
    cuts = [x[0]]
    for left, right in zip(centres, centres[1:]):
        between = (x > left) & (x < right)
        cuts.append(x[between][np.argmin(surface[between])])
    cuts.append(x[-1])
    return [np.sum(surface[(x >= a) & (x < b)]) * (x[1] - x[0]) for a, b in zip(cuts, cuts[1:])]


def generate_pipe(c, seed):
    """A bead along a pipe, draped over it, wandering off the crest."""
    rng = np.random.default_rng(seed)
    p, swing, _ = paths(c, rng, 1)
    x_fine = np.arange(-c.field_half_mm - 2, c.field_half_mm + 2, c.fine_mm)
    pipe = np.sqrt(np.clip(c.radius_mm**2 - (x_fine - c.crest_x_mm) ** 2, 0, None)) - c.radius_mm
    a0, h0 = 0.5 * c.width_mm, c.aspect * 0.5 * c.width_mm
    off = c.wander_mm * np.sin(2 * math.pi * p / (0.8 * c.length_mm) + rng.uniform(0, 6.3))
    surfaces, truth = np.zeros((p.size, x_fine.size)), []
    for i in range(p.size):
        s = math.sqrt(swing[i, 0])
        centre = c.crest_x_mm + off[i]
        rise, _ = cap(c, (x_fine - centre) / (s * a0))
        gain = s * h0 * rise
        surfaces[i] = pipe + gain
        truth.append((i, 0, np.sum(gain) * c.fine_mm, centre, 2 * s * a0, s * h0, np.nan))
    x_sensor, z = sensed(c, rng, x_fine, surfaces, c.standoff_mm)
    return p, x_sensor, z, truth


def write(out_dir, c, p, x_sensor, z, truth, rig_part):
    os.makedirs(out_dir, exist_ok=True)
    with open(os.path.join(out_dir, "scan.csv"), "w") as f:
        f.write("profile,t_s,layer,path_mm,frame_z_mm,x_mm,z_mm\n")
        for i in range(p.size):
            head = f"{i},{p[i] / 20.0:.6f},0,{p[i]:.5f},{c.standoff_mm:.5f},"
            zs = ["" if math.isnan(v) else f"{v:.5f}" for v in z[i]]
            f.write("".join(f"{head}{xv:.4f},{zv}\n" for xv, zv in zip(x_sensor, zs)))
    with open(os.path.join(out_dir, "truth_roads.csv"), "w") as f:
        f.write("profile,bead,area_mm2,center_x_mm,width_mm,height_mm,naive_area_mm2\n")
        for row in truth:
            f.write("{},{},{:.6f},{:.6f},{:.6f},{:.6f},{:.6f}\n".format(*row))
    edge, ref = c.field_half_mm, c.reference_mm
    with open(os.path.join(out_dir, "rig.yaml"), "w") as f:
        f.write(
            f"name: roads-pipe\npart:\n{rig_part}sensor:\n"
            f"  reference_areas_mm: [[{-edge}, {-edge + ref}], [{edge - ref}, {edge}]]\n"
        )


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("what", choices=("roads", "pipe"))
    ap.add_argument("out_dir")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--cap", choices=("cosine", "parabola"), default=Config.cap)
    ap.add_argument("--ratio", type=float, default=Config.ratio, help="roads: centre spacing over a lone road's width")
    ap.add_argument("--roads", type=int, default=Config.roads)
    ap.add_argument("--laid", choices=("left-first", "right-first"), default=Config.laid, help="roads: the laying order")
    ap.add_argument("--radius-mm", type=float, default=Config.radius_mm, help="pipe: its radius")
    ap.add_argument("--wander-mm", type=float, default=Config.wander_mm, help="pipe: the bead's greatest distance off the crest")
    ap.add_argument("--fit-radius", action="store_true", help="pipe: the rig file leaves the radius out")
    args = ap.parse_args()
    c = Config()
    c.cap, c.ratio, c.roads, c.laid = args.cap, args.ratio, args.roads, args.laid
    c.radius_mm, c.wander_mm = args.radius_mm, args.wander_mm
    if args.what == "roads":
        write(args.out_dir, c, *generate_roads(c, args.seed), "  bed: flat\n")
    else:
        radius = "" if args.fit_radius else f"  bed_radius_mm: {c.radius_mm}\n"
        write(args.out_dir, c, *generate_pipe(c, args.seed), "  bed: cylinder\n" + radius)


if __name__ == "__main__":
    main()
