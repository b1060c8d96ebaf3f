"""A second part generator, written from docs/data-formats.md alone (not
from libbead/sim): a wall of tamped beads printed around a contour with
rounded corners, written as another tool would (the long-form part CSV,
the nozzle log CSV and a rig file), with the truth beside it.

It differs from the twin (sim/part_twin.h) where a generator can:
  - the bead's cross-section is a stadium, not a superellipse: a tamper
    holds its height at the layer height H, its sides are half circles of
    diameter H and its top and bottom flat (large-scale printing's pressed
    bead); the flow the layer height cannot take widens it;
  - its flat bottom fills down to whatever the layer below left under it
    and its rounded sides overhang, hiding the notch between two layers
    from a sensor looking down;
  - the flow is the extruder's: a screw command varying in time, the melt
    lagging it by a first-order delay, printed without a stop from layer
    to layer (the layer's start is where the last one ended);
  - the head slows through each corner (lateral acceleration) and speeds
    up out of it (tangential acceleration), so the bead widens there;
  - each sensor point is the surface averaged over the laser spot (a
    point on a wall's face is a mix), with noise and dropouts;
  - the head misses its line by a shift per pass that the scan does not
    record, and each layer's bead wanders off the head's line.

Units: mm, s. Run: python3 tamped_wall.py OUT_DIR [--seed N]."""
import argparse
import math
import os

import numpy as np


class Config:
    length_mm, width_mm, corner_radius_mm = 100.0, 60.0, 6.0
    layers = 6
    layer_height_mm = 2.0
    speed_mm_s = 20.0
    lateral_accel_mm_s2 = 45.0
    tangential_accel_mm_s2 = 60.0
    flow_mm3_s = 240.0  # the screw's command, mean
    flow_wave = 0.07  # its relative swing ...
    flow_period_s = 11.0  # ... and period
    melt_lag_s = 0.35  # the melt's first-order lag behind the screw
    displacement_mm3_per_rev = 120.0
    profile_spacing_mm = 0.5
    trail_mm = 25.0  # the laser line behind the nozzle
    points, field_half_mm = 801, 20.0
    spot_mm = 0.05  # the laser spot each point averages over
    noise_mm = 0.01
    dropout = 1.0 / 300.0
    pass_shift_sigma_mm = 0.2
    wander_sigma_mm = 0.25
    standoff_mm = 60.0
    fine_mm = 0.005  # the generator's own grid across the wall
    # "tamped": the stadium above; "pressed": an ellipse of this aspect
    # (half-height over half-width) whose top the nozzle holds at the layer
    # height, sunk into what lies under it, wider where more is laid;
    # "lens": the same with two parabolas for the ellipse.
    shape = "tamped"
    aspect = 0.5
    # Every length (and the noise) this many times the above, the times
    # kept: speeds and accelerations scaled with the lengths, flows with
    # their cubes (a glue bead at 0.1, a large-scale printer's at 4).
    scale = 1.0


def scaled(c, k):
    """c with every length k times (Config.scale)."""
    for name in ("length_mm", "width_mm", "corner_radius_mm", "layer_height_mm", "speed_mm_s",
                 "lateral_accel_mm_s2", "tangential_accel_mm_s2", "profile_spacing_mm", "trail_mm",
                 "field_half_mm", "spot_mm", "noise_mm", "pass_shift_sigma_mm", "wander_sigma_mm",
                 "standoff_mm", "fine_mm"):
        setattr(c, name, getattr(c, name) * k)
    c.flow_mm3_s *= k**3
    c.displacement_mm3_per_rev *= k**3
    c.scale *= k
    return c


def contour(c, step=None):
    """The rounded rectangle's path length and curvature radius at each
    step (inf on the straights); the path starts midway along a long side."""
    step = 0.01 * c.scale if step is None else step
    straight_l, straight_w = c.length_mm - 2 * c.corner_radius_mm, c.width_mm - 2 * c.corner_radius_mm
    arc = 0.5 * math.pi * c.corner_radius_mm
    pieces = [0.5 * straight_l, arc, straight_w, arc, straight_l, arc, straight_w, arc, 0.5 * straight_l]
    bends = [False, True, False, True, False, True, False, True, False]
    perimeter = sum(pieces)
    p = np.arange(0.0, perimeter + step / 2, step)
    radius = np.full(p.size, np.inf)
    start = 0.0
    for length, bend in zip(pieces, bends):
        if bend:
            radius[(p >= start) & (p < start + length)] = c.corner_radius_mm
        start += length
    return p, radius, perimeter


def head_speed(c, p, radius):
    """The speed along the path: at most the straights' speed, v^2 / R at
    most the lateral limit in a bend, and changed no faster than the
    tangential limit (a forward and a backward sweep over v^2)."""
    v2 = np.minimum(c.speed_mm_s**2, c.lateral_accel_mm_s2 * radius)
    dp = p[1] - p[0]
    for order in (range(1, p.size), range(p.size - 2, -1, -1)):
        for i in order:
            j = i - 1 if order.step == 1 else i + 1
            v2[i] = min(v2[i], v2[j] + 2 * c.tangential_accel_mm_s2 * dp)
    return np.sqrt(v2)


def melt_flow(c, t):
    """The screw's command (mm^3/s) and the melt's flow lagging it (the
    exact first-order response to the sine, past its transient)."""
    w = 2 * math.pi / c.flow_period_s
    command = c.flow_mm3_s * (1 + c.flow_wave * np.sin(w * t))
    gain, phase = 1 / math.sqrt(1 + (w * c.melt_lag_s) ** 2), math.atan(w * c.melt_lag_s)
    melt = c.flow_mm3_s * (1 + c.flow_wave * gain * np.sin(w * t - phase))
    return command, melt


def stadium(x, centre, base, height, width):
    """The stadium's top and bottom over x (NaN outside it)."""
    r = 0.5 * height
    u = np.abs(x - centre) - (0.5 * width - r)
    inside = np.abs(x - centre) <= 0.5 * width
    rise = np.sqrt(np.clip(r * r - np.maximum(u, 0) ** 2, 0, None))
    rise = np.where(u > 0, rise, r)
    top = np.where(inside, base + r + rise, np.nan)
    bottom = np.where(inside, np.where(u > 0, base + r - rise, base), np.nan)
    return top, bottom


def added_area(x, surface, centre, base, height, width):
    """The material a stadium adds over `surface`: its flat bottom fills
    down to the surface, its rounded sides only where they reach it."""
    r = 0.5 * height
    top, bottom = stadium(x[None, :], centre[:, None], base, height, width[:, None])
    flat = np.abs(x[None, :] - centre[:, None]) <= 0.5 * width[:, None] - r
    lower = np.where(flat, surface, np.maximum(surface, bottom))
    return np.nansum(np.clip(top - lower, 0, None), axis=1) * (x[1] - x[0]), top


def pressed(x, surface, centre, top_z, aspect, a, lens=False):
    """A pressed ellipse's material over `surface` (what it overlaps of the
    old material stays the old's) and its top (NaN outside it). lens: two
    parabolas, top and bottom, meeting at a corner at each end (none of
    the model's superellipses)."""
    b = aspect * a
    u = (x[None, :] - centre[:, None]) / a[:, None]
    rise = np.clip(1 - u * u, 0, None)
    half = b[:, None] * (rise if lens else np.sqrt(rise))
    inside = np.abs(u) < 1
    top = np.where(inside, top_z - b[:, None] + half, np.nan)
    bottom = np.where(inside, top_z - b[:, None] - half, np.nan)
    return np.nansum(np.clip(top - np.fmax(surface, bottom), 0, None), axis=1) * (x[1] - x[0]), top


def lay_pressed(c, x, surface, centre, base, area):
    """Each profile's pressed ellipse of the given area: its half-width by
    Newton's steps on a difference quotient."""
    window = np.abs(x) <= 11.0 * c.scale
    xw, sw = x[window], surface[:, window]
    top_z = base + c.layer_height_mm
    a = np.sqrt(area / (math.pi * c.aspect))
    for _ in range(8):
        got, _ = pressed(xw, sw, centre, top_z, c.aspect, a, c.shape == "lens")
        da = 1e-3 * c.scale
        more, _ = pressed(xw, sw, centre, top_z, c.aspect, a + da, c.shape == "lens")
        a = np.clip(a + (area - got) * da / np.maximum(more - got, 1e-9 * c.scale**2), 0.5 * c.scale, 12.0 * c.scale)
    material, top = pressed(xw, sw, centre, top_z, c.aspect, a, c.shape == "lens")
    after = surface.copy()
    after[:, window] = np.where(np.isnan(top), sw, np.fmax(sw, top))
    k = np.searchsorted(x, centre)
    rows = np.arange(area.size)
    return after, material, 2 * a, after[rows, k] - surface[rows, k]


def lay_layer(c, x, surface, centre, base, area):
    """Each profile's stadium of the given area, the surface it leaves and
    the gain at its centre. Its width by Newton's steps: a wider stadium
    adds the layer height per mm while its sides stay clear of the old
    surface, which they nearly do (within the window of x its sides
    reach: beyond it the surface stays as it was). Where a wider bead's
    flat bottom reaches past the bead below, each mm of width fills down a
    layer or more beside it: the step is kept inside a bracket of widths
    whose areas lie either side of the target, halving it where the step
    leaves it (a step taken as h per mm swung about the answer without
    reaching it: a layer laid 26 % over its flow, 0.43 layer heights off
    the one below)."""
    if c.shape in ("pressed", "lens"):
        return lay_pressed(c, x, surface, centre, base, area)
    h = c.layer_height_mm
    window = np.abs(x) <= 12.0 * c.scale
    xw, sw = x[window], surface[:, window]
    width = np.maximum(area / h + (1 - math.pi / 4) * h, 1.5 * h)
    lo, hi = np.full_like(width, 1.2 * h), np.full_like(width, 24.0 * c.scale)
    for _ in range(16):
        got, _ = added_area(xw, sw, centre, base, h, width)
        lo, hi = np.where(got < area, width, lo), np.where(got < area, hi, width)
        step = width + (area - got) / h
        width = np.where((step >= lo) & (step <= hi), step, 0.5 * (lo + hi))
    material, top = added_area(xw, sw, centre, base, h, width)
    after = surface.copy()
    after[:, window] = np.where(np.isnan(top), sw, np.fmax(sw, top))
    k = np.searchsorted(x, centre)
    rows = np.arange(area.size)
    height = after[rows, k] - surface[rows, k]
    return after, material, width, height


def spot_average(x_fine, surface, x_at, spot):
    """The surface averaged over the spot around each x_at (rows: profiles)."""
    dx = x_fine[1] - x_fine[0]
    cum = np.concatenate([np.zeros((surface.shape[0], 1)), np.cumsum(surface, axis=1) * dx], axis=1)
    edges = np.concatenate([[x_fine[0] - dx / 2], x_fine + dx / 2])
    out = np.empty(x_at.shape)
    for r in range(surface.shape[0]):
        a = np.interp(x_at[r] - spot / 2, edges, cum[r])
        b = np.interp(x_at[r] + spot / 2, edges, cum[r])
        out[r] = (b - a) / spot
    return out


def generate(c, seed):
    rng = np.random.default_rng(seed)
    p_grid, radius, perimeter = contour(c)
    v_grid = head_speed(c, p_grid, radius)
    # The head's time along one layer (the path walked without a stop,
    # layer after layer: the next starts where this one ended).
    dt = np.diff(p_grid) / (0.5 * (v_grid[1:] + v_grid[:-1]))
    t_layer = np.concatenate([[0.0], np.cumsum(dt)])
    layer_s = t_layer[-1]
    shifts = rng.normal(0, c.pass_shift_sigma_mm, c.layers)
    wander = rng.normal(0, c.wander_sigma_mm, c.layers)
    centre_bed = shifts + wander  # each layer's bead in the bed frame
    x_fine = np.arange(-c.field_half_mm - 2 * c.scale, c.field_half_mm + 2 * c.scale, c.fine_mm)
    x_sensor = np.linspace(-c.field_half_mm, c.field_half_mm, c.points)

    def nozzle_time(layer, p):
        return layer * layer_s + np.interp(p, p_grid, t_layer)

    def laid_area(layer, p):
        _, melt = melt_flow(c, nozzle_time(layer, p))
        return melt / np.interp(p, p_grid, v_grid)

    profiles, truth = [], []
    for n in range(c.layers):
        phase = rng.uniform(0, c.profile_spacing_mm)
        p = np.arange(phase, perimeter - c.trail_mm, c.profile_spacing_mm)
        surface = np.zeros((p.size, x_fine.size))  # the bed
        for j in range(n + 1):
            centre = np.full(p.size, centre_bed[j])
            surface, material, width, height = lay_layer(
                c, x_fine, surface, centre, j * c.layer_height_mm, laid_area(j, p)
            )
            if j + 1 == n:
                below_centre = centre_bed[j]
        # The profile at p: when the nozzle was trail_mm ahead, or past
        # the layer's end (on the next layer's start), in its own frame.
        t_scan = nozzle_time(n, p + c.trail_mm)
        x_bed = x_sensor[None, :] + shifts[n]
        seen = spot_average(x_fine, surface, np.repeat(x_bed, p.size, axis=0), c.spot_mm)
        frame_z = n * c.layer_height_mm + c.standoff_mm
        z = seen - frame_z + rng.normal(0, c.noise_mm, seen.shape)
        z[rng.random(z.shape) < c.dropout] = np.nan
        profiles.append((n, p, t_scan, frame_z, z))
        offset = centre_bed[n] - below_centre if n > 0 else 0.0
        truth.append((n, p, nozzle_time(n, p), material, height, width, centre_bed[n] - shifts[n], offset))
    # The nozzle's log at 100 Hz: layer, path, screw command, head speed.
    t_log = np.arange(0.0, c.layers * layer_s, 0.01)
    layer_log = np.minimum((t_log // layer_s).astype(int), c.layers - 1)
    path_log = np.interp(t_log - layer_log * layer_s, t_layer, p_grid)
    command, _ = melt_flow(c, t_log)
    log = (t_log, layer_log, path_log, 60 * command / c.displacement_mm3_per_rev, np.interp(path_log, p_grid, v_grid))
    return profiles, truth, log, x_sensor


def write(out_dir, c, profiles, truth, log, x_sensor):
    os.makedirs(out_dir, exist_ok=True)
    with open(os.path.join(out_dir, "scan.csv"), "w") as f:
        f.write("profile,t_s,layer,path_mm,frame_z_mm,frame_x_mm,x_mm,z_mm\n")
        k = 0
        for n, p, t, frame_z, z in profiles:
            for i in range(p.size):
                head = f"{k},{t[i]:.6f},{n},{p[i]:.5f},{frame_z:.5f},0,"
                zs = ["" if math.isnan(v) else f"{v:.5f}" for v in z[i]]
                f.write("".join(f"{head}{xv:.4f},{zv}\n" for xv, zv in zip(x_sensor, zs)))
                k += 1
    with open(os.path.join(out_dir, "log.csv"), "w") as f:
        f.write("t_s,layer,path_mm,screw_rpm,head_speed_mm_s\n")
        for row in zip(*log):
            f.write(f"{row[0]:.4f},{row[1]},{row[2]:.5f},{row[3]:.5f},{row[4]:.5f}\n")
    with open(os.path.join(out_dir, "truth.csv"), "w") as f:
        f.write("layer,path_mm,t_nozzle_s,area_mm2,height_mm,width_mm,center_x_mm,offset_below_mm,flow_mm3_s\n")
        for n, p, t, area, height, width, centre, offset in truth:
            _, melt = melt_flow(c, t)
            for i in range(p.size):
                f.write(
                    f"{n},{p[i]:.5f},{t[i]:.6f},{area[i]:.6f},{height[i]:.6f},{width[i]:.6f},"
                    f"{centre:.6f},{offset:.6f},{melt[i]:.6f}\n"
                )
    edge, area = c.field_half_mm, 7 * c.scale
    with open(os.path.join(out_dir, "rig.yaml"), "w") as f:
        f.write(
            "name: tamped-wall\npart:\n  bed: flat\nsensor:\n"
            f"  reference_areas_mm: [[{-edge}, {-edge + area}], [{edge - area}, {edge}]]\n"
        )


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("out_dir")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--layers", type=int, default=Config.layers)
    ap.add_argument("--spacing-mm", type=float, default=None, help="the sensor's point spacing (points over the field, 40 mm times the scale)")
    ap.add_argument("--contour-mm", type=float, nargs=2, default=None, help="the contour's length and width")
    ap.add_argument("--shape", choices=("tamped", "pressed", "lens"), default="tamped")
    ap.add_argument("--scale", type=float, default=1.0, help="every length (and the noise) this many times")
    ap.add_argument("--spot-mm", type=float, default=Config.spot_mm,
                    help="the laser spot each point averages over (a small value: points that do not average)")
    args = ap.parse_args()
    c = Config()
    c.shape = args.shape
    c.spot_mm = args.spot_mm
    c.layers = args.layers
    if args.contour_mm:
        c.length_mm, c.width_mm = args.contour_mm
    scaled(c, args.scale)
    if args.spacing_mm:
        c.points = int(round(2 * c.field_half_mm / args.spacing_mm)) + 1
    write(args.out_dir, c, *generate(c, args.seed))


if __name__ == "__main__":
    main()
