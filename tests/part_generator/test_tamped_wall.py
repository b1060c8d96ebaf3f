"""Part scans another generator made (tamped_wall.py: written from the
formats alone), carried through as a user would: bead import of its CSV
and log, bead measure, bead flow.

A wall of tamped beads (the model's stadium, part/superellipse.h: a flat
top, half-circle sides, the height held by the tamper): the issue's bars,
the area seen counting the notch a tamped bead hides and the corrected
area not.

A wall of pressed ellipses (the model's shape, laid by other physics: the
nozzle holds the top at the layer height and more material widens the
bead): the issue's bars for a six-layer wall on a contour with corners."""
import os
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from cli import run  # noqa: E402
import score  # noqa: E402
import tamped_wall  # noqa: E402


def measured(c, seed, d):
    """The generator's scan imported, measured and flowed in d; the figures
    and what bead measure said."""
    tamped_wall.write(d, c, *tamped_wall.generate(c, seed=seed))
    run("import", os.path.join(d, "scan.csv"), "--profile-column", "profile", "--time-column", "t_s",
        "--x-column", "x_mm", "--z-column", "z_mm", "--layer-column", "layer", "--path-column", "path_mm",
        "--frame-z-column", "frame_z_mm", "--frame-x-column", "frame_x_mm", "--log", os.path.join(d, "log.csv"),
        "-o", os.path.join(d, "part.h5"))
    rig = os.path.join(d, "rig.yaml")
    said = run("measure", os.path.join(d, "part.h5"), "--rig", rig, "-o", os.path.join(d, "geom.csv"))
    run("flow", os.path.join(d, "part.h5"), "--rig", rig, "-o", os.path.join(d, "flow.csv"))
    f = score.score(d)
    print(f)
    return f, said


def corrected_above_bed(d):
    """The measured geometry, and of its valid rows above the bed (where the
    beads overhang) how many have a corrected area and how many there are."""
    geom = score.columns(os.path.join(d, "geom.csv"))
    above = (geom["layer"] > 0) & (geom["valid"] == 1)
    return geom, int(np.sum(above & np.isfinite(geom["area_corrected_mm2"]))), int(above.sum())


def test_a_tamped_wall_from_another_generator(tmp_path):
    c = tamped_wall.Config()
    c.layers, c.length_mm, c.width_mm = 3, 70.0, 40.0
    d = str(tmp_path)
    f, said = measured(c, 3, d)

    # Every profile a bead, its height the layer's (the generator's truth
    # is the gain at the bead's centre; the tool's, at its crest: on a flat
    # top the same within the noise), and each place's nozzle time exact.
    assert f["valid"] == f["profiles"] == f["corrected"]
    assert f["height_median_abs_mm"] < 0.05
    assert f["time_error_s"] < 1e-3

    # The area seen holds the notches under the beads' rounded sides: over
    # the material by about 2 r^2 (1 - pi / 4) / area, 3-4 % on the bed,
    # more on the layers above (two notches, and the wander's overhangs).
    assert f["seen_run_bias"] > 0.02

    # The bars (#37), the beads taken for stadiums and held as a
    # tamped bead's (their height and their ends' arcs in mm, their aspect
    # from their own width). Seed 3 gives -0.18 %, 0.21 %, 0.015 mm, 94.1 %
    # and 100 % covered; before the stadium, every row was left uncorrected
    # (the area seen +12 %, its flow fit -188 %).
    assert abs(f["corrected_run_bias"]) < 0.01
    assert f["corrected_median_abs"] < 0.03
    assert f["flow_fit"] >= 85.0
    assert f["covered_95"] >= 0.90, f
    pools = [line for line in said.splitlines() if "half-height over half-width" in line]
    assert len(pools) == c.layers and all("a stadium" in line for line in pools), said
    # Each layer's half-height, the generator's r = H / 2 (1 mm), within two
    # of its sigmas.
    held = [line for line in said.splitlines() if "held as a tamped bead's" in line]
    assert len(held) == c.layers, said
    for line in held:
        b, sigma = (float(v) for v in line.split("half-height ")[1].split(" mm")[0].split(" +- "))
        assert abs(b - 0.5 * c.layer_height_mm) <= 2.0 * sigma, line

    # The wall's wander (each bead's centre less the one below's, where the
    # pass's shift was found) within a point spacing, the sensor's grid, at
    # the 95th percentile: a flat top's middle is read where its ends' arcs
    # cross a level, each crossing to a fraction of a spacing. (Read as the
    # vertex of a parabola about the highest point, anywhere on the 4 mm
    # flat: 1.1 mm off, median, on a wall of seed 5.)
    geom, truth = score.columns(os.path.join(d, "geom.csv")), score.columns(os.path.join(d, "truth.csv"))
    wander = geom["offset_below_mm"] - truth["offset_below_mm"]
    wander = wander[np.isfinite(wander)]
    assert wander.size > 0.5 * f["profiles"]
    assert np.percentile(np.abs(wander), 95) < 2.0 * c.field_half_mm / (c.points - 1), np.percentile(np.abs(wander), 95)


def test_a_tamped_walls_upper_layers_over_deep_columns_keep_their_intervals(tmp_path):
    """Six tamped layers (the generator's default wall) seen through a spot
    as wide as the point spacing: a layer that overhangs the one below
    hides a column down the wall beside it, deeper layer by layer, and its
    rows' errors grow with that column. Each layer's 95 % intervals hold
    at least 90 % of its rows (about 570: the share's sampling sigma is
    0.9 %-points at 95 %, five of them above 90 %). Seed 1 before the
    surface below's steps were counted under a footprint (part/
    hidden_groove.cc: GrooveSum): the sixth layer 84.4 %, its errors 0.115
    mm^2 RMS at sigmas of 0.041 (98.8 % with them)."""
    c = tamped_wall.Config()
    d = str(tmp_path)
    f, said = measured(c, 1, d)
    assert c.layers == 6 and f["valid"] == f["profiles"] == f["corrected"]
    assert "the profiler's points average over a footprint" in said, said
    layers = score.by_layer(d)
    assert len(layers) == c.layers
    for layer in layers:
        assert layer["covered_95"] >= 0.9, layer


def test_a_pressed_wall_from_another_generator(tmp_path):
    c = tamped_wall.Config()
    c.shape, c.length_mm, c.width_mm = "pressed", 70.0, 40.0
    d = str(tmp_path)
    f, said = measured(c, 4, d)
    assert c.layers == 6 and f["valid"] == f["profiles"] == f["corrected"]
    # The bars (#37): the area the layer added within 1 % over the
    # run and 3 % per profile (median), the layer height within 0.05 mm,
    # the flow along the path fit at least 85 % to the melt's true flow.
    # Seed 4 gives -0.07 %, 0.16 %, 0.008 mm and 94.2 %.
    assert abs(f["corrected_run_bias"]) < 0.01
    assert f["corrected_median_abs"] < 0.03
    assert f["height_median_abs_mm"] < 0.05
    assert f["flow_fit"] >= 85.0
    # The sensor's view alone is far off: the correction is what passes.
    assert f["seen_run_bias"] > 0.05 and f["seen_flow_fit"] < 0.0
    # The corrected areas' 95 % intervals: the generator's points average
    # over a spot as wide as their spacing, mixing each wall's foot into the
    # bead's end (part/silhouette_top.h: OnTheTop; PooledShape::footprint).
    # 74.2 % before the mixed points were told apart (56 % on the sixth
    # layer); 96.8 % before the layer below's steps were counted.
    assert f["covered_95"] >= 0.9
    # Where within the spot each end lies its points cannot tell, and that
    # is the same in every row: each layer's pooled aspect (the generator's
    # 0.5) was 0.497-0.499 +- 0.001-0.002 (the rows' spread alone), and the
    # second layer's rows, which share it, were covered 89 % (0.8 sigmas
    # low on average; 53 % at seed 1). Held as the spot leaves it (+-0.004-
    # 0.005), every pool holds the truth within two sigmas and every layer's
    # intervals at least 90 % of its rows (seed 4: 99.5-100 %, the first
    # layer's 96.7 %). (The first layer's beads, on the bed, are fitted, not
    # placed at walls: its pool says 0.49825 +- 0.00040, the fits' spread
    # alone, and says so; printed to three decimals it read 0.498 +- 0.000.)
    lines = [line for line in said.splitlines() if "half-height over half-width" in line]
    pools = [line for line in lines if ", exponent " in line]
    assert len(pools) == c.layers - 1, said
    for line in lines:
        aspect, sigma = (float(v) for v in line.split("half-width ")[1].split(",")[0].split(";")[0].split(" +- "))
        assert sigma > 0.0, line
        if line in pools:
            assert abs(aspect - c.aspect) <= 2.0 * sigma, line
        else:
            assert "the fitted beads' spread alone" in line, line
    assert "the shape's sigmas hold it" in said, said
    for layer in score.by_layer(d):
        assert layer["covered_95"] >= 0.9, layer
    # The head slows through the corners and the beads bulge: where a bulge
    # begins or ends between two profiles of the layer below, the blend of
    # the two cannot say where, and the tool says so (on an aspect of 0.7,
    # those rows were corrected 0.1-0.4 mm^2 off at sigmas of 0.01).
    assert "steps between its two profiles around them" in said, said


def test_a_coarser_sensors_pressed_wall_keeps_the_bars(tmp_path):
    """The same wall seen by a sensor of half the points (401 over 40 mm:
    0.1 mm apart). Each bead's ends lie somewhere in their walls' cells,
    which are twice as wide; as the wall wanders the ends sweep through
    their cells and, placed at the cells' middles, every row's groove
    followed the phase (a sawtooth of +-0.4 mm^2 on the sixth layer, over
    20 mm of path): the flow fit 84.5-84.9 % (seeds 4, 5). Placed where the
    held shape's top puts them (part/silhouette.cc: PlaceByTop), 89.8 and
    87.4 %."""
    c = tamped_wall.Config()
    c.shape, c.length_mm, c.width_mm, c.points = "pressed", 70.0, 40.0, 401
    f, said = measured(c, 5, str(tmp_path))
    assert f["valid"] == f["profiles"] == f["corrected"]
    assert abs(f["corrected_run_bias"]) < 0.01
    assert f["corrected_median_abs"] < 0.03
    assert f["height_median_abs_mm"] < 0.05
    assert f["flow_fit"] >= 85.0
    assert f["covered_95"] >= 0.9


def test_a_lens_wall_is_not_corrected_as_a_superellipse(tmp_path):
    """Beads of two parabolas meeting at a corner at each end (none of the
    model's shapes, its top fitted by a superellipse to 1.7 times the noise):
    the shape solved over the tops puts the ends off the walls in most rows,
    and the tool says so rather than correct them (they came out 11 % high
    at 17-85 of their sigmas before it looked)."""
    c = tamped_wall.Config()
    c.shape, c.layers, c.length_mm, c.width_mm = "lens", 4, 70.0, 40.0
    d = str(tmp_path)
    f, said = measured(c, 4, d)
    assert f["valid"] == f["profiles"]
    geom, corrected, above = corrected_above_bed(d)
    # The layers above the bed, where the beads overhang: no confident wrong
    # number. Where a corrected area is given, its 95 % interval holds.
    if corrected:
        assert f["covered_95"] >= 0.90, f
    assert corrected < 0.1 * above, (corrected, above)
    assert "puts an end off the wall the profile shows" in said or "misses its beads' tops" in said, said
    # On the bed a lens hides nothing (its lower half is in the bed, no
    # overhang): the tool does not describe the shape it cannot see.
    assert "bead shape: not seen" in said, said
    # ... and no flow is given from the area seen there (it counts the
    # groove the overhangs hide: 11 % high), each such row kept, invalid,
    # with the area seen in it; the bed's rows keep their flow. (Given from
    # the area seen, and said, before.)
    flowed = run("flow", os.path.join(d, "part.h5"), "--rig", os.path.join(d, "rig.yaml"), "-o", os.path.join(d, "f.csv"))
    refused = (geom["valid"] == 1) & ~np.isfinite(geom["area_corrected_mm2"])
    assert f"{int(np.sum(refused))} measured profiles have no flow (valid 0)" in flowed, flowed
    flow = score.columns(os.path.join(d, "f.csv"))
    assert np.all(flow["valid"][refused] == 0) and np.all(np.isnan(flow["flow_mm3_s"][refused]))
    placed = np.isfinite(flow["t_s"])  # (the log had the nozzle there)
    assert np.all(np.isfinite(flow["area_mm2"][refused & placed]))
    bed = (geom["valid"] == 1) & (geom["layer"] == 0)
    assert np.mean(flow["valid"][bed] == 1) > 0.95
    # A layer with no flow has no volume, and the total says it is not the
    # part's.
    assert "layer 1: no volume (none of its profiles has a flow" in flowed, flowed
    assert "layers, those with a flow: not the part's" in flowed, flowed


def test_a_coarser_sensors_lens_wall_is_not_corrected_in_any_layer(tmp_path):
    """The lens wall seen by a sensor of a quarter the points (201 over 40
    mm: 0.2 mm apart), six layers. Layers whose walls show judge the shape
    none of the model's; a layer showing too few walls to judge its own
    carries the exponent of the layers below, and with it their verdict.
    (Given the exponent alone, the sixth layer was corrected as the third's
    superellipse: 10 % high, half its intervals covering.)"""
    c = tamped_wall.Config()
    c.shape, c.layers, c.length_mm, c.width_mm, c.points = "lens", 6, 70.0, 40.0, 201
    d = str(tmp_path)
    f, said = measured(c, 17, d)
    assert f["valid"] == f["profiles"]
    _, corrected, above = corrected_above_bed(d)
    assert corrected < 0.1 * above, (corrected, above, said)
    assert "walls showed (this layer shows too few walls to judge its own" in said, said


def test_a_glue_beads_wall_a_tenth_the_size_keeps_the_bars(tmp_path):
    """The pressed wall at a tenth of its size (a glue bead 0.6 mm wide,
    0.2 mm layers, seen over +-2 mm by a sensor of points 5 um apart with
    1 um of noise: tamped_wall.Config.scale). Every length scales, so every
    figure should hold as it does at full size. The layer below's shift was
    searched over +-3 mm, wider than the field: no point lay over the
    surface below at every shift, every shift's cost was 0, no shift was
    found on any layer, and 283 profiles of the third and fourth layers
    were refused (the flow fit -32 %)."""
    c = tamped_wall.scaled(tamped_wall.Config(), 0.1)
    c.shape, c.layers, c.length_mm, c.width_mm = "pressed", 4, 7.0, 4.0
    f, said = measured(c, 1, str(tmp_path))
    assert f["valid"] == f["profiles"] == f["corrected"]
    assert said.count("pass shift not found") == 0, said
    assert abs(f["corrected_run_bias"]) < 0.01
    assert f["corrected_median_abs"] < 0.03
    assert f["height_median_abs_mm"] < 0.1 * 0.05
    assert f["flow_fit"] >= 85.0
    assert f["covered_95"] >= 0.9


def test_a_fast_tamped_walls_every_layer_is_a_stadium(tmp_path):
    """Laid at 40 mm/s, tamped beads are 4.8 mm wide for 2 mm high. Over
    their tops a tall, boxy superellipse follows them nearly as well as
    their own stadium, and a row takes the stadium only where the other
    misses by four of its sigmas: 33-45 % of each layer's rows placed at
    their walls took it, though the superellipse left the larger residual in
    almost every row (by 0.50-0.56 in ln, over the layers). One layer's pool
    went with the rest, a superellipse of aspect 1.38 and exponent 4.4, and
    corrected that layer 13.6 % high at sigmas covering 82 % of the rows
    (flow fit -61 %). The rows' evidence, pooled, chooses each layer's
    family."""
    c = tamped_wall.Config()
    c.speed_mm_s, c.layers, c.length_mm, c.width_mm = 40.0, 4, 70.0, 40.0
    d = str(tmp_path)
    f, said = measured(c, 5, d)
    assert f["valid"] == f["profiles"] == f["corrected"]
    assert abs(f["corrected_run_bias"]) < 0.01
    assert f["corrected_median_abs"] < 0.03
    assert f["flow_fit"] >= 85.0
    assert f["covered_95"] >= 0.9
    pools = [line for line in said.splitlines() if "half-height over half-width" in line]
    assert len(pools) == c.layers and all("a stadium" in line for line in pools), said
    for layer in score.by_layer(d):
        assert abs(layer["bias"]) < 0.01, layer


def test_a_fast_tamped_walls_layers_above_hold_a_tamped_shape(tmp_path):
    """The same wall six layers high (another draw). In layers 2-5 most of
    the first rows' walls show at both ends but their tops alone do not pin
    a free shape standing over them; layer 3 had too few rows placed to
    solve its own. It was judged by its rows' own fits at the carried
    exponent with a free aspect (1.22, where the layers that solved their
    own shapes pooled 0.26-0.34), whose tops missed by over 3 tolerances:
    the whole layer was left uncorrected and its flow, from the area seen,
    was 16 % high (flow fit -49 %). Then the shape carried from below was
    held at each row's width (flow fit 88.9 %); now, the rows' evidence
    favouring the stadium, each such layer's rows are placed as stadiums
    and the layer solves its own (89.6 %). Either way every layer holds a
    tamped bead's shape, in mm."""
    c = tamped_wall.Config()
    c.speed_mm_s, c.layers, c.length_mm, c.width_mm = 40.0, 6, 70.0, 40.0
    d = str(tmp_path)
    f, said = measured(c, 5, d)
    layers = said.split("  layer ")[1:]
    held = [k for k, text in enumerate(layers) if "held as a tamped bead's" in text or "tamped bead, carried" in text]
    assert held == list(range(c.layers)), said
    assert f["valid"] == f["profiles"] == f["corrected"]
    assert abs(f["corrected_run_bias"]) < 0.01
    assert f["flow_fit"] >= 85.0
    assert f["covered_95"] >= 0.9


def test_the_generator_lays_the_material_its_flow_gives_beside_an_offset_bead():
    """The generator's truth is Q = v A: each tamped bead it lays holds the
    area its flow over the head's speed gives, wherever the bead below
    lies. Three layers in line, the fourth 0.85 mm (0.43 layer heights)
    beside the third: a wider bead's flat bottom fills down beside the one
    below, a mm of width adding more than the layer height, and a width
    solved by steps of h per mm swung about the answer (this fourth bead
    was laid 24 % over its flow; on a large printer's wall, four times the
    size, 26 % over it through a corner, the truth's flow no longer its area
    times the speed: the tool's flow fit was 63 % against it, 94 % since)."""
    c = tamped_wall.Config()
    x = np.arange(-c.field_half_mm - 2.0, c.field_half_mm + 2.0, c.fine_mm)
    surface = np.zeros((1, x.size))
    for layer, (centre, area) in enumerate(((-0.097, 12.5), (-0.569, 12.5), (-0.133, 12.5), (0.717, 15.6))):
        surface, material, _, _ = tamped_wall.lay_layer(
            c, x, surface, np.array([centre]), layer * c.layer_height_mm, np.array([area]))
        # (The width's grid, fine_mm, holds the area to a cell's share.)
        assert abs(material[0] / area - 1.0) < 1e-6, (layer, material[0], area)


def test_a_noisy_tamped_walls_shape_is_placed_by_its_family(tmp_path):
    """Tamped beads seen with 30 um of noise (1.5 % of their height): each
    bead's walls show at both ends, but most of its top's points pin a
    free shape too poorly to stand over them (either family within the
    noise, the superellipse's exponent free), so no layer's shape was
    solved, an ellipse was assumed, it was not their outline, and every row
    was left uncorrected, its flow from the area seen (flow fit -279 %).
    Over the layer's rows the stadium follows the tops better than the
    superellipse beyond their noise: the rows are placed again as stadiums
    alone, and each layer's shape is solved and held."""
    c = tamped_wall.Config()
    c.layers, c.length_mm, c.width_mm, c.noise_mm = 3, 70.0, 40.0, 0.03
    d = str(tmp_path)
    f, said = measured(c, 5, d)
    assert f["valid"] == f["profiles"] == f["corrected"], said
    assert "the stadium's family followed the tops better than the superellipse's" in said, said
    # Bars as the quiet wall's: the noise is in the sigmas, not the bias.
    assert abs(f["corrected_run_bias"]) < 0.01
    assert f["corrected_median_abs"] < 0.03
    assert f["flow_fit"] >= 85.0
    assert f["covered_95"] >= 0.9
    for layer in score.by_layer(d):
        assert abs(layer["bias"]) < 0.01, layer


def test_a_coarse_pressed_walls_unsolved_shape_stays_an_ellipse(tmp_path):
    """Pressed ellipses seen at points 0.2 mm apart: on the bed most beads'
    walls show at both ends (about 0.55 mm high) but their tops do not pin
    a free shape standing over them by more than the ends' cells leave in
    doubt. The rows' evidence does not favour the stadium (an ellipse is in
    both families), so none is forced on them: the ellipse is assumed and
    the words say why."""
    c = tamped_wall.Config()
    c.shape, c.layers, c.length_mm, c.width_mm, c.points = "pressed", 3, 70.0, 40.0, 201
    d = str(tmp_path)
    f, said = measured(c, 15, d)
    bed = said.split("  layer 1:")[0]
    assert "show walls at both ends, but the shape each one's top solves does not stand over them" in bed, said
    assert "stadium's family followed the tops better" not in said, said
    assert f["valid"] == f["profiles"] == f["corrected"]
    assert abs(f["corrected_run_bias"]) < 0.01
    assert f["covered_95"] >= 0.9


def test_a_coarse_pressed_walls_bead_beside_the_cliff_below_is_placed_at_its_own_wall(tmp_path):
    """Six layers of pressed ellipses seen at points 0.2 mm apart. In the
    sixth, the bead's side lies on the fifth's shoulder, and past it the
    wall below drops to the bed: that cliff, read at another pass's points,
    left gains of 0.7-1.2 mm past the bead's end, the largest rise there,
    two points out. The shape placed at it missed the top by 5 tolerances;
    the layer's shape was refused and its 370 rows left uncorrected (their
    flow from the area seen: flow fit -44 %). Where that rise steps over a
    cliff, the next is tried and taken where the top fits."""
    c = tamped_wall.Config()
    c.shape, c.length_mm, c.width_mm, c.points = "pressed", 70.0, 40.0, 201
    f, said = measured(c, 15, str(tmp_path))
    assert f["valid"] == f["profiles"] == f["corrected"], said
    sixth = said.split("  layer 5:")[1]
    assert "beads placed at the rise inside the largest, which steps over the cliff" in sixth, said
    assert abs(f["corrected_run_bias"]) < 0.01
    assert f["corrected_median_abs"] < 0.03
    assert f["covered_95"] >= 0.9
    # (Below the 85 %: at 0.2 mm the ends' cells' phase moves each
    # row's groove; the seen area's flow fit, -158 %.)
    assert f["flow_fit"] >= 70.0
