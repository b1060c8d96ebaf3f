"""Roads side by side and a bead along a pipe from another generator
(roads_pipe.py: written from the formats alone; cosine caps that keep
their material, spot-averaged points), imported from its CSV and measured
as a user would: bead import, bead measure (--beads all for the roads).

The issue's bars (#37) on shapes the twin never lays: the right number of
roads in 95 % of the profiles (90 % at 0.70 of their width), centres
within 0.3 mm, each road's area within 5 % (median) at 0.85 and 1.05; a
bead wandering 3 mm off the crest of a 40 mm pipe within 2 % per profile
and 1 % over the run."""
import os
import sys

import numpy as np
import pytest

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from cli import run  # noqa: E402
import roads_pipe  # noqa: E402
import score  # noqa: E402


def imported(d):
    run("import", os.path.join(d, "scan.csv"), "--profile-column", "profile", "--time-column", "t_s",
        "--x-column", "x_mm", "--z-column", "z_mm", "--layer-column", "layer", "--path-column", "path_mm",
        "--frame-z-column", "frame_z_mm", "-o", os.path.join(d, "part.h5"))
    return os.path.join(d, "part.h5"), os.path.join(d, "rig.yaml")


@pytest.mark.parametrize("ratio", [0.70, 0.85, 1.05])
def test_roads_from_another_generator(tmp_path, ratio):
    c = roads_pipe.Config()
    c.ratio = ratio
    d = str(tmp_path)
    roads_pipe.write(d, c, *roads_pipe.generate_roads(c, 7), "  bed: flat\n")
    part, rig = imported(d)
    said = run("measure", part, "--rig", rig, "--beads", "all", "-o", os.path.join(d, "roads.csv"))
    f = score.score_roads(d)
    print(ratio, f)
    assert f["right_count"] >= (0.90 if ratio < 0.8 else 0.95), said
    # Centres: the apex of a cap two hundred points wide, placed within a
    # few hundredths of a mm (seed 7: under 0.02 mm); the bar is 0.3.
    assert f["centre_max_mm"] < 0.3
    # Areas: the noise over a road's ~120 points is ~0.1 % of its area.
    # The bar is 5 % at 0.85 and 1.05; the tool holds it at 0.70 too,
    # where a cut at the valley gives the later road's material to the
    # earlier one by several times that.
    assert max(f["area_median_abs_by_road"]) < 0.05
    if ratio < 0.8:
        assert max(f["naive_median_abs_by_road"]) > 2 * max(f["area_median_abs_by_road"])
    # The split rests on the laying order where roads overlap, and the
    # profile cannot show it: the tool says so.
    words = "cannot show the order" if ratio < 1.0 else "do not rest on the order"
    assert words in said, said


def test_roads_laid_right_to_left(tmp_path):
    """Told the order, the split holds; the default order would hand the
    valleys' material the wrong way, and the words say by how much."""
    c = roads_pipe.Config()
    c.ratio, c.laid = 0.70, "right-first"
    d = str(tmp_path)
    roads_pipe.write(d, c, *roads_pipe.generate_roads(c, 3), "  bed: flat\n")
    part, rig = imported(d)
    said = run("measure", part, "--rig", rig, "--beads", "all", "--laid", "right-first", "-o", os.path.join(d, "roads.csv"))
    f = score.score_roads(d)
    assert f["right_count"] >= 0.90 and max(f["area_median_abs_by_road"]) < 0.05, f
    wrong = run("measure", part, "--rig", rig, "--beads", "all", "-o", os.path.join(d, "wrong.csv"))
    g = score.score_roads(d, "wrong.csv")
    # Seed 3: the outer roads 15-17 % off in the wrong order, and the tool
    # says a median of 9.5 % would move (21.9 % at the 95th percentile).
    assert max(g["area_median_abs_by_road"]) > 0.05, g
    assert "laid right to left, each road's area would be" in wrong, wrong
    assert "laid left to right, each road's area would be" in said, said


@pytest.mark.parametrize("fit_radius", [False, True])
def test_a_bead_along_a_pipe_from_another_generator(tmp_path, fit_radius):
    c = roads_pipe.Config()
    d = str(tmp_path)
    rig_part = "  bed: cylinder\n" + ("" if fit_radius else f"  bed_radius_mm: {c.radius_mm}\n")
    roads_pipe.write(d, c, *roads_pipe.generate_pipe(c, 7), rig_part)
    part, rig = imported(d)
    run("measure", part, "--rig", rig, "-o", os.path.join(d, "geom.csv"))
    g, t = score.columns(os.path.join(d, "geom.csv")), score.columns(os.path.join(d, "truth_roads.csv"))
    assert np.all(g["valid"] == 1)
    # The bead wanders 3 mm off the crest, the crest 1.3 mm off the field's
    # middle: the arc through the bare pipe either side is what it stands
    # on. Seed 7: 0.1 % per profile (0.3 % with the radius fitted).
    rel = g["area_mm2"] / t["area_mm2"] - 1.0
    assert np.median(np.abs(rel)) < 0.02
    assert abs(g["area_mm2"].sum() / t["area_mm2"].sum() - 1.0) < 0.01
