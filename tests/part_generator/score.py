"""The figures #37 judges a wall by, from the tool's geometry and flow
CSVs against a generator's truth (rows in the scan's order, one per
profile): the area the layer added over the run and per profile, the
layer height, the flow along the path, and the naive layer subtraction
(the area seen) beside the corrected area.

Run: python3 score.py DIR (geom.csv, flow.csv, truth.csv in DIR)."""
import csv
import math
import os
import sys

import numpy as np


def number(text):
    try:
        return float(text)
    except ValueError:
        return math.nan  # empty, or a word (status)


def columns(path):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    return {k: np.array([number(r[k]) for r in rows]) for k in rows[0]}


def fit(estimate, truth):
    """100 (1 - |e - t| / |t - mean t|) over the rows both have."""
    ok = np.isfinite(estimate) & np.isfinite(truth)
    e, t = estimate[ok], truth[ok]
    return 100.0 * (1.0 - np.linalg.norm(e - t) / np.linalg.norm(t - t.mean()))


def covered_95(err, sigma):
    """The share of errors inside their 95 % interval, +-1.96 sigma."""
    return float(np.mean(np.abs(err) <= 1.96 * sigma)) if err.size else math.nan


def score(directory):
    geom = columns(os.path.join(directory, "geom.csv"))
    truth = columns(os.path.join(directory, "truth.csv"))
    flow = columns(os.path.join(directory, "flow.csv"))
    assert geom["area_mm2"].size == truth["area_mm2"].size == flow["flow_mm3_s"].size
    valid = geom["valid"] == 1
    corrected = geom["area_corrected_mm2"]
    has = valid & np.isfinite(corrected)
    out = {"profiles": int(valid.size), "valid": int(valid.sum()), "corrected": int(has.sum())}
    for name, area, rows in (("corrected", corrected, has), ("seen", geom["area_mm2"], valid)):
        if not rows.any():
            out[name + "_run_bias"] = out[name + "_median_abs"] = math.nan
            continue
        rel = area[rows] / truth["area_mm2"][rows] - 1.0
        out[name + "_run_bias"] = area[rows].sum() / truth["area_mm2"][rows].sum() - 1.0
        out[name + "_median_abs"] = float(np.median(np.abs(rel)))
    sigma = geom["area_corrected_sigma_mm2"][has]
    err = corrected[has] - truth["area_mm2"][has]
    out["covered_95"] = covered_95(err, sigma)
    out["height_median_abs_mm"] = float(np.median(np.abs(geom["height_mm"][valid] - truth["height_mm"][valid])))
    # The flow against the melt's true flow at the time the tool gives.
    out["flow_fit"] = fit(np.where(flow["valid"] == 1, flow["flow_mm3_s"], math.nan), truth["flow_mm3_s"])
    seen_flow = flow["head_speed_mm_s"] * flow["area_mm2"]
    out["seen_flow_fit"] = fit(np.where(flow["valid"] == 1, seen_flow, math.nan), truth["flow_mm3_s"])
    out["time_error_s"] = float(np.nanmedian(np.abs(flow["t_s"] - truth["t_nozzle_s"])))
    return out


def by_layer(directory):
    """Per layer, over the rows with a corrected area: how many, their 95 %
    intervals' coverage, the mean error over sigma (a layer's shared error
    shows here), the bias over the material, the median sigma and the
    errors' RMS (mm^2)."""
    geom = columns(os.path.join(directory, "geom.csv"))
    truth = columns(os.path.join(directory, "truth.csv"))
    err = geom["area_corrected_mm2"] - truth["area_mm2"]
    sigma = geom["area_corrected_sigma_mm2"]
    has = (geom["valid"] == 1) & np.isfinite(err)
    out = []
    for layer in np.unique(geom["layer"]):
        m = has & (geom["layer"] == layer)
        if not m.any():
            continue
        e, s = err[m], sigma[m]
        out.append({"layer": int(layer), "rows": int(m.sum()), "covered_95": covered_95(e, s),
                    "mean_z": float(np.mean(e / s)), "bias": float(e.sum() / truth["area_mm2"][m].sum()),
                    "median_sigma_mm2": float(np.median(s)), "rms_error_mm2": float(np.sqrt(np.mean(e * e)))})
    return out


def score_roads(directory, measured="roads.csv"):
    """Roads side by side (bead measure --beads all against truth_roads.csv):
    the share of profiles with the right number of beads; over those, the
    beads' centre errors (the largest and the 95th percentile, mm) and the
    median relative area error by road, beside a vertical cut at the
    valleys' (the generator's naive_area_mm2)."""
    got = columns(os.path.join(directory, measured))
    truth = columns(os.path.join(directory, "truth_roads.csv"))
    profiles = np.unique(truth["profile"])
    right, centre, area, naive = 0, [], [], []
    for k in profiles:
        g, t = got["profile"] == k, truth["profile"] == k
        if g.sum() != t.sum():
            continue
        right += 1
        centre.append(got["center_x_mm"][g] - truth["center_x_mm"][t])
        area.append(got["area_mm2"][g] / truth["area_mm2"][t] - 1.0)
        naive.append(truth["naive_area_mm2"][t] / truth["area_mm2"][t] - 1.0)
    out = {"profiles": int(profiles.size), "right_count": right / profiles.size}
    if right:
        c, a = np.abs(np.array(centre)), np.array(area)
        out["centre_max_mm"] = float(np.nanmax(c))
        out["centre_p95_mm"] = float(np.nanpercentile(c, 95))
        out["area_median_abs_by_road"] = [float(v) for v in np.nanmedian(np.abs(a), axis=0)]
        out["area_bias_by_road"] = [float(v) for v in np.nanmean(a, axis=0)]
        out["naive_median_abs_by_road"] = [float(v) for v in np.nanmedian(np.abs(np.array(naive)), axis=0)]
    return out


if __name__ == "__main__":
    if os.path.exists(os.path.join(sys.argv[1], "truth_roads.csv")):
        for key, value in score_roads(sys.argv[1]).items():
            print(f"{key}: {value}")
        sys.exit(0)
    for key, value in score(sys.argv[1]).items():
        print(f"{key}: {value:.4f}" if isinstance(value, float) else f"{key}: {value}")
    for row in by_layer(sys.argv[1]):
        print("  ".join(f"{k} {v:.4f}" if isinstance(v, float) else f"{k} {v}" for k, v in row.items()))
