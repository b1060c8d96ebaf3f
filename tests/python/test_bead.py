"""`import bead` on the bundled sample run: the module's answers are the
command's, row for row; arrays come back without a copy; errors are
bead.Error with the tool's one-line message."""
import csv
import json
import math
import os
import subprocess

import numpy as np
import pytest

import bead

SOURCE = os.environ.get("BEAD_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", ".."))
RIG = os.path.join(SOURCE, "testdata", "sample", "rig.yaml")
RUN = os.path.join(SOURCE, "testdata", "sample", "run.h5")
CLI = os.environ.get("BEAD_CLI", "bead")


def read_csv(path):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    return rows


def number(text):
    return math.nan if text == "" else float(text)


def same(a, b):
    return (math.isnan(a) and math.isnan(b)) or a == b


def run_cli(*args):
    done = subprocess.run([CLI, *args], capture_output=True, text=True)
    assert done.returncode == 0, done.stdout + done.stderr
    return done.stdout


def test_measure_run_is_bead_measure_row_for_row(tmp_path):
    out = tmp_path / "geometry.csv"
    run_cli("measure", "--rig", RIG, RUN, "-o", str(out))
    rows = read_csv(out)
    g = bead.measure_run(RIG, RUN)
    assert len(g["profile"]) == len(rows)
    for i, row in enumerate(rows):
        for key, text in row.items():
            if key == "status":
                assert g[key][i] == text, (i, key)
            elif key == "valid":
                assert bool(g[key][i]) == (text == "1"), (i, key)
            else:
                assert same(float(g[key][i]), number(text)), (i, key, g[key][i], text)


def test_flow_is_bead_flow_row_for_row(tmp_path):
    out = tmp_path / "flow.csv"
    run_cli("flow", "--rig", RIG, RUN, "-o", str(out))
    rows = read_csv(out)
    f = bead.flow(RIG, RUN)
    assert len(f["profile"]) == len(rows)
    for i, row in enumerate(rows):
        for key, text in row.items():
            if key == "valid":
                assert bool(f[key][i]) == (text == "1"), (i, key)
            elif text == "" and not f["valid"][i]:
                continue  # the CSV leaves an invalid sample's numbers empty
            else:
                assert same(float(f[key][i]), number(text)), (i, key, f[key][i], text)
    assert f["total_volume_mm3"] > 0


def test_a_block_from_numpy_measures_as_the_run_does():
    r = bead.read_run(RUN)
    n, p = r["z_mm"].shape
    assert r["t_s"].shape == (n,) and r["x_mm"].shape[-1] == p and r["z_mm"].dtype == np.float32
    # Handed over without a copy: NumPy does not own the library's buffer.
    assert not r["z_mm"].flags["OWNDATA"] and r["z_mm"].base is not None
    areas = [[-24.0, -12.0], [12.0, 24.0]]  # the sample rig's sensor.reference_areas_mm
    g = bead.measure(r["x_mm"], r["z_mm"], areas)
    whole = bead.measure_run(RIG, RUN, occlusion="none")
    np.testing.assert_array_equal(g["valid"], whole["valid"])
    np.testing.assert_array_equal(g["area_mm2"], whole["area_mm2"])
    # float64 input is converted once and gives the same.
    g64 = bead.measure(r["x_mm"].astype(np.float64), r["z_mm"].astype(np.float64), areas)
    np.testing.assert_array_equal(g64["area_mm2"], g["area_mm2"])


def test_errors_are_bead_errors_with_the_tools_message(tmp_path):
    with pytest.raises(bead.Error, match="nothere.h5"):
        bead.read_run(str(tmp_path / "nothere.h5"))
    with pytest.raises(bead.Error, match="z_mm must be 2-D"):
        bead.measure(np.zeros(3, np.float32), np.zeros(3, np.float32), [[-1, 0], [0, 1]])
    with pytest.raises(bead.Error, match="reference_areas_mm"):
        bead.measure(np.zeros(3, np.float32), np.zeros((2, 3), np.float32), [[-1, 0]])
    assert issubclass(bead.Error, RuntimeError)


def test_help_gives_units():
    assert "mm" in bead.measure.__doc__ and "mm^2" in bead.measure_run.__doc__
    assert bead.__version__ == run_cli("--version").split()[1]


def test_the_example_runs_on_the_sample():
    example = os.path.join(SOURCE, "examples", "python", "measure_with_module.py")
    done = subprocess.run(["/usr/bin/python3", example, RIG, RUN], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert "volume" in done.stdout and "profiles of" in done.stdout
    g = bead.measure_run(RIG, RUN)
    assert "valid %d;" % g["valid"].sum() in done.stdout


def test_simulate_identify_and_tune(tmp_path):
    config = tmp_path / "sim.yaml"
    config.write_text("seed: 3\nduration_s: 2\nsensor: {points: 100}\n")
    out = bead.simulate(str(config), str(tmp_path / "twin"))
    r = bead.read_run(os.path.join(out, "run.h5"))
    assert r["z_mm"].shape[1] == 100 and r["log"] is not None
    # A first-order process (gain 2, 0.5 s) under a random binary input.
    rng = np.random.default_rng(7)
    t = np.arange(3000) * 0.01
    u = np.repeat(rng.choice([-1.0, 1.0], 60), 50)
    y = np.zeros_like(t)
    for k in range(1, len(t)):  # exact zero-order hold of 2 / (0.5 s + 1)
        a = math.exp(-0.01 / 0.5)
        y[k] = a * y[k - 1] + 2 * (1 - a) * u[k - 1]
    m = bead.identify(t, u, y + rng.normal(0, 0.01, len(t)), poles=1, zeros=0)
    assert m["fit_percent"] > 95
    assert abs(m["num"][-1] / m["den"][-1] - 2) < 0.05
    assert m["prediction"].shape == t.shape
    # Seed 004's eq. 14 and its Table I row 4 (kp 10.836, ki 0.7611, kd 21.032).
    c = bead.tune([1.0033], [174.14596084, 179.28493203, 48.1046, 1.0])
    assert c["ok"] and abs(c["kp"] - 10.836) < 0.01 * 10.836
    # Thesis eq. 22 has a direct feedthrough and a delay: refused, with the reason.
    f = bead.tune([9.175, 149.2, 905.3], [1, 12.84, 47.52], 0.15, method="simc")
    assert not f["ok"] and any("unstable" in reason for reason in f["reasons"])
    with pytest.raises(bead.Error, match="direct feedthrough"):
        bead.tune([9.175, 149.2, 905.3], [1, 12.84, 47.52], 0.15)


def test_explain_is_bead_explain_on_the_same_series(tmp_path):
    # A first-order process (gain 2, 0.5 s) under a random binary input, and
    # a drift of the output the model lacks (0.4 over the 40 s): the
    # module's report is the command's on the same numbers written as CSV.
    rng = np.random.default_rng(11)
    t = np.arange(4000) * 0.01
    u = np.repeat(rng.choice([-1.0, 1.0], 80), 50)
    y = np.zeros_like(t)
    a = math.exp(-0.01 / 0.5)
    for k in range(1, len(t)):
        y[k] = a * y[k - 1] + 2 * (1 - a) * u[k - 1]
    y += 0.01 * t + rng.normal(0, 0.02, len(t))
    data = tmp_path / "series.csv"
    with open(data, "w") as f:
        f.write("t_s,u,y\n")
        for row in zip(t, u, y):
            f.write("%r,%r,%r\n" % row)
    out = tmp_path / "explain.json"
    run_cli("explain", str(data), "--time", "t_s", "--input", "u", "--output", "y", "--poles", "1", "--zeros", "0",
            "-o", str(out))
    with open(out) as f:
        cli = json.load(f)
    py = bead.explain(t, u, y, poles=1, zeros=0, output="y")
    assert py["effects_added"] == cli["effects_added"]
    assert py["model"]["num"] == cli["model"]["num"] and py["model"]["delay_s"] == cli["model"]["delay_s"]
    assert py["fit_after_pct"] == cli["fit_after_pct"]
    assert any("drift" in e["name"] for e in py["effects_added"]), py["effects_added"]
    assert py["compare"]["measured"] == cli["compare"]["measured"]
    with pytest.raises(bead.Error, match="one length"):
        bead.explain(t, u[:-1], y)


def compare_rows(columns, rows, flags):
    for i, row in enumerate(rows):
        for key, text in row.items():
            if key == "status":
                assert columns[key][i] == text, (i, key)
            elif key in flags:
                assert bool(columns[key][i]) == (text == "1"), (i, key)
            elif text == "":
                assert math.isnan(float(columns[key][i])), (i, key, columns[key][i])
            else:
                assert same(float(columns[key][i]), number(text)), (i, key, columns[key][i], text)


def test_a_part_scan_is_read_measured_and_flowed_as_the_commands_do(tmp_path):
    config = tmp_path / "wall.yaml"
    config.write_text("seed: 2\npart:\n  layers: 3\n  length_mm: 15\n")
    run_cli("simulate", str(config), "-o", str(tmp_path / "sim"))
    rig, scan = str(tmp_path / "sim" / "rig.yaml"), str(tmp_path / "sim" / "part.h5")
    d = bead.read_run(scan)
    assert d["kind"] == "part" and "encoder" not in d
    assert d["layer"].dtype == np.int64 and d["layer"].shape == d["t_s"].shape
    assert set(["layer", "path_mm"]) <= set(d["log"].keys())
    run_cli("measure", "--rig", rig, scan, "-o", str(tmp_path / "geo.csv"))
    rows = read_csv(tmp_path / "geo.csv")
    g = bead.measure_part(rig, scan)
    assert len(g["profile"]) == len(rows) == len(d["t_s"])
    compare_rows(g, rows, {"valid", "shift_found"})
    run_cli("flow", "--rig", rig, scan, "-o", str(tmp_path / "flow.csv"))
    rows = read_csv(tmp_path / "flow.csv")
    f = bead.part_flow(rig, scan)
    compare_rows(f, rows, {"valid"})
    assert sorted(f["layer_volume_mm3"]) == [0, 1, 2]


def test_a_part_profile_is_measured_as_it_arrives(tmp_path):
    # The twin's wall fed profile by profile, as acquisition software would:
    # each layer's area seen against the twin's truth within the walls'
    # bound (0.15 mm^2 rms: each of four walls within a 0.05 mm spacing at
    # up to 1.5 mm high, tests/part/part_wall_test.cc), layer 0 on the bed.
    config = tmp_path / "wall.yaml"
    config.write_text("seed: 3\npart:\n  layers: 3\n  length_mm: 20\n")
    run_cli("simulate", str(config), "-o", str(tmp_path / "sim"))
    d = bead.read_run(str(tmp_path / "sim" / "part.h5"))
    truth = read_csv(tmp_path / "sim" / "truth.csv")
    p = bead.PartProfileProcessor(str(tmp_path / "sim" / "rig.yaml"), max_points=d["z_mm"].shape[1])
    errors = []
    for k in range(len(d["t_s"])):
        x = d["x_mm"] if d["x_mm"].ndim == 1 else d["x_mm"][k]  # one x for every profile, or each its own
        g = p.process(x, d["z_mm"][k], int(d["layer"][k]), float(d["path_mm"][k]),
                      float(d["frame_x_mm"][k]), float(d["frame_z_mm"][k]))
        assert g["valid"], (k, g["status"], g["why"])
        errors.append(g["area_mm2"] - float(truth[k]["visible_area_mm2"]))
        if d["layer"][k] > 0:
            assert np.isfinite(g["shift_mm"])
    assert np.sqrt(np.mean(np.square(errors))) < 0.15
    with pytest.raises(ValueError, match="1-D arrays of one length"):
        p.process(d["z_mm"][0], d["z_mm"][0][:5], 0, 0.0)


def test_identify_refuses_a_model_of_the_datas_opposite_sign():
    # The heater step searched for delays up to 10 s falls in a basin whose
    # gain has the data's opposite sign (README, the step-test chain): the
    # command writes no model for it, and the module hands none back.
    path = os.path.join(SOURCE, "testdata", "step", "heater_step.csv")
    rows = read_csv(path)
    t, u, y = (np.array([float(r[k]) for r in rows]) for k in ("t_s", "heater_cmd_c", "temp_c"))
    with pytest.raises(bead.Error, match="opposite sign"):
        bead.identify(t, u, y, structure="P2D", max_delay_s=10)
    m = bead.identify(t, u, y, structure="P2D", max_delay_s=5)
    assert abs(m["num"][-1] / m["den"][-1] - 1.0) < 0.01  # eq. 14's unit gain
