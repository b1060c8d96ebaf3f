#!/usr/bin/env python3
"""Draws `bead report`'s page from the numbers the command wrote.

    bead_report.py DATA_DIR OUT.html [--explain explain.json]

DATA_DIR holds about.csv, geometry.csv, lines.csv and profiles.csv, and
when there were: flow.csv, pin_points.csv, pin_fits.csv, pin_offset.csv
(written by `bead report`; the geometry and flow CSVs are libbead's result
CSVs). A part scan's (about.csv's kind: part) are part_report.py's. The page is one file: pictures are PNG inside it (base64), no
script, no link to anything outside. Written atomically.
"""
import html
import json
import math
import os
import sys

try:
    import matplotlib.pyplot as plt
    import numpy as np

    import part_report
    from report_common import number, png, read_csv, table, write_page
except ImportError as missing:  # the command words the fix (exit 3)
    sys.stderr.write("bead report: %s\n" % missing)
    sys.exit(3)

STATUS_COLOURS = {"too_few_points": "#999999", "no_reference": "#d62728", "no_bead": "#bcbd22",
                  "bead_edge_not_seen": "#ff7f0e", "bead_in_reference_area": "#9467bd"}


def profiles_figure(points, lines):
    ids = [int(p) for p in lines["profile"]]
    fig, axes = plt.subplots(1, len(ids), figsize=(3.2 * len(ids), 3.0), sharey=False, squeeze=False)
    for ax, k, pid in zip(axes[0], range(len(ids)), ids):
        sel = points["profile"] == pid
        x, z = points["x_mm"][sel], points["z_mm"][sel]
        ax.plot(x, z, ".", ms=2, color="#1f77b4", label="points")
        c, m = lines["intercept_mm"][k], lines["slope"][k]
        if math.isfinite(c):
            xs = np.array([x.min(), x.max()]) if len(x) else np.array([0, 1])
            ax.plot(xs, c + m * xs, "-", color="k", lw=0.8, label="reference line")
            thr = lines["threshold_mm"][k]
            if math.isfinite(thr):
                ax.plot(xs, c + m * xs + thr * math.sqrt(1 + m * m), ":", color="#777", lw=0.8, label="threshold")
        left, right = lines["left_edge_x_mm"][k], lines["right_edge_x_mm"][k]
        if math.isfinite(left) and math.isfinite(right):
            inside = (x >= left) & (x <= right)
            ax.fill_between(x[inside], (c + m * x)[inside], z[inside], color="#2ca02c", alpha=0.35, label="measured area")
            for e in (left, right):
                ax.axvline(e, color="#2ca02c", lw=0.8)
            pad = 0.6 * (right - left)
            ax.set_xlim(left - pad, right + pad)
            zs = z[(x >= left - pad) & (x <= right + pad)]
            if len(zs):
                ax.set_ylim(zs.min() - 0.2, zs.max() + 0.3)
        title = "profile %d, t %.2f s" % (pid, lines["t_s"][k])
        area, corr = lines["area_mm2"][k], lines["area_corrected_mm2"][k]
        if math.isfinite(area):
            title += "\n%.3f mm²" % area
            if math.isfinite(corr):
                title += ", hidden %.3f mm² (%.1f %%)" % (area - corr, 100 * (area - corr) / area)
        else:
            title += "\n" + lines["status"][k]
        ax.set_title(title, fontsize=8)
        ax.set_xlabel("x, mm")
        ax.tick_params(labelsize=7)
    axes[0][0].set_ylabel("z, mm")
    axes[0][0].legend(fontsize=6, loc="upper left")
    return png(fig)


def geometry_figure(g):
    t = g["t_s"]
    valid = g["valid"] == 1
    fig, axes = plt.subplots(3, 1, figsize=(10, 6.2), sharex=True)
    for ax, key, label in zip(axes, ("area_mm2", "width_mm", "height_mm"), ("area, mm²", "width, mm", "height, mm")):
        ax.plot(t[valid], g[key][valid], "-", lw=0.6, color="#1f77b4", label="measured")
        if key == "area_mm2" and np.isfinite(g["area_corrected_mm2"]).any():
            ax.plot(t[valid], g["area_corrected_mm2"][valid], "-", lw=0.6, color="#d62728", label="occlusion-corrected")
        ax.set_ylabel(label)
        lo = np.nanmin(g[key][valid]) if valid.any() else 0
        for status, colour in STATUS_COLOURS.items():
            sel = np.array([s == status for s in g["status"]])
            if sel.any():
                ax.plot(t[sel], np.full(sel.sum(), lo), "|", color=colour, ms=6,
                        label="invalid: %s (%d)" % (status, sel.sum()) if ax is axes[0] else None)
    axes[0].legend(fontsize=7, ncol=3, loc="lower right")
    axes[-1].set_xlabel("measurement time, s")
    return png(fig)


def flow_figure(f, explain):
    t, q = f["t_s"], f["flow_mm3_s"]
    ok = f["valid"] == 1
    fig, ax = plt.subplots(figsize=(10, 3.2))
    ax.plot(t[ok], q[ok], "-", lw=0.7, color="#1f77b4", label="flow Q = v A")
    if "flow_sigma_mm3_s" in f and np.isfinite(f["flow_sigma_mm3_s"][ok]).any():
        s = f["flow_sigma_mm3_s"][ok]
        ax.fill_between(t[ok], q[ok] - 2 * s, q[ok] + 2 * s, color="#1f77b4", alpha=0.25, lw=0, label="±2σ (area)")
    ax.set_xlabel("extrusion time, s")
    ax.set_ylabel("flow, mm³/s")
    if explain:
        ax.set_title("model fit %.2f %% before, %.2f %% after the effects added" %
                     (explain.get("fit_before_pct", math.nan), explain.get("fit_after_pct", math.nan)), fontsize=9)
    ax.legend(fontsize=7)
    return png(fig)


def spectrum_figure(spectrum, unexplained, effects):
    """The residual's spectrum on a log frequency axis (0 Hz left out), each
    marked peak labelled with its frequency and what it tracks."""
    fig, ax = plt.subplots(figsize=(10, 3.2))
    lo = math.inf
    for key, colour in (("before", "#7f7f7f"), ("after", "#1f77b4")):
        s = spectrum.get(key)
        if s and s.get("frequency_hz"):
            f = np.array(s["frequency_hz"], dtype=float)
            p = np.maximum(np.array(s["power"], dtype=float), 1e-12)
            keep = f > 0
            if keep.any():
                lo = min(lo, f[keep].min())
                ax.loglog(f[keep], p[keep], lw=0.7, color=colour, label="residual " + key)
    # The unexplained peaks by what they track; the residual's peaks before
    # that are not among them were taken by the effects added.
    def short(tracks):
        return "unexplained" if tracks.startswith("frequency") else tracks + ", unexplained"

    marks = [(u.get("frequency_hz"), short(u.get("tracks", "")), "#d62728")
             for u in unexplained if isinstance(u.get("frequency_hz"), (int, float))]
    names = ", ".join(e.get("name", "") for e in effects)
    after = [p.get("frequency_hz") for p in (spectrum.get("after") or {}).get("peaks", []) if isinstance(p, dict)]

    def near(f, others):
        return any(isinstance(g, (int, float)) and abs(f - g) <= 0.02 * f for g in others)

    for peak in (spectrum.get("before") or {}).get("peaks", []):
        f = peak.get("frequency_hz") if isinstance(peak, dict) else None
        if names and isinstance(f, (int, float)) and f > 0 and not near(f, [m[0] for m in marks] + after):
            marks.append((f, "taken by " + names, "#2ca02c"))
    for k, (f, label, colour) in enumerate(sorted(marks)):
        ax.axvline(f, color=colour, lw=0.6, ls="--")
        ax.text(f, 0.98 if k % 2 == 0 else 0.62, "%.3g Hz %s" % (f, label), rotation=90, fontsize=6, va="top",
                ha="right", color=colour, transform=ax.get_xaxis_transform())
    if math.isfinite(lo):
        ax.set_xlim(left=lo)
    ax.set_xlabel("frequency, Hz (log)")
    ax.set_ylabel("power")
    ax.legend(fontsize=7, loc="lower left")
    return png(fig)


def compare_figure(compare, explain):
    """MATLAB's compare: the measured output and the model's, before and
    after the effects, with each one's fit."""
    t = np.array(compare["t_s"], dtype=float)
    fig, ax = plt.subplots(figsize=(10, 3.4))
    ax.plot(t, np.array(compare["measured"], dtype=float), "-", lw=0.6, color="#444444", label="measured")
    ax.plot(t, np.array(compare["model_before"], dtype=float), "-", lw=0.9, color="#ff7f0e",
            label="model alone: fit %.2f %%" % explain.get("fit_before_pct", math.nan))
    ax.plot(t, np.array(compare["model_after"], dtype=float), "-", lw=0.9, color="#1f77b4",
            label="model with the effects: fit %.2f %%" % explain.get("fit_after_pct", math.nan))
    ax.set_xlabel("time, s")
    unit = compare.get("unit", "")
    ax.set_ylabel("flow, mm³/s" if unit == "mm3_s" else (unit or "output"))
    ax.legend(fontsize=7, loc="lower right")
    return png(fig)


def resid_figure(diagnostics):
    """MATLAB's resid: the residual's autocorrelation and its cross-
    correlation with the input, before and after, with their 99 % bounds
    (2.58 / sqrt(N))."""
    fig, axes = plt.subplots(1, 2, figsize=(10, 3.0))
    for ax, key, title in ((axes[0], "whiteness", "autocorrelation of the residual"),
                           (axes[1], "input_correlation", "cross-correlation with the input")):
        for when, colour in (("before", "#7f7f7f"), ("after", "#1f77b4")):
            d = diagnostics.get("%s_%s" % (key, when)) or {}
            values = d.get("acf" if key == "whiteness" else "ccf") or []
            m = d.get("lags") if isinstance(d.get("lags"), int) else 0
            # acf: lags 1..M; ccf: lags -M..M (explain.md)
            lags = list(range(1, m + 1)) if key == "whiteness" else list(range(-m, m + 1))
            values = [math.nan if v is None else v for v in values]
            if m > 0 and len(lags) == len(values):
                ax.plot(lags, values, ".-", ms=3, lw=0.6, color=colour, label=when)
                b = d.get("bound")
                if isinstance(b, (int, float)) and math.isfinite(b):
                    ax.axhline(b, color=colour, lw=0.6, ls=":")
                    ax.axhline(-b, color=colour, lw=0.6, ls=":")
        ax.set_title(title, fontsize=9)
        ax.set_xlabel("lag, samples")
        ax.legend(fontsize=7)
    return png(fig)


def offset_rows(explain):
    """The encoder offset from the run beside the rig file's and the pins'."""
    rows = []
    o = explain.get("offset_from_run_counts")
    prof = explain.get("offset_profile") or {}
    lo, hi = prof.get("ci95_low_counts"), prof.get("ci95_high_counts")
    if isinstance(o, (int, float)):
        pinned = explain.get("offset_from_run_pinned")
        interval = ("%s to %s" % (number(lo, "%.1f"), number(hi, "%.1f"))) if pinned else \
            "not pinned by this run (offset and delay trade: %s)" % number(explain.get("offset_delay_correlation"), "%.3f")
        rows.append(("from the run", number(o, "%.1f") if pinned else "-", interval))
    if isinstance(explain.get("rig_offset_counts"), (int, float)):
        rows.append(("rig file", number(explain["rig_offset_counts"], "%.1f"), ""))
    if isinstance(explain.get("pin_offset_counts"), (int, float)):
        ci = explain.get("pin_offset_ci95_counts")
        rows.append(("pin scans", number(explain["pin_offset_counts"], "%.1f"), "± %s" % number(ci, "%.1f")))
    if isinstance(explain.get("combined_offset_counts"), (int, float)):
        rows.append(("run and pins combined", number(explain["combined_offset_counts"], "%.1f"),
                     "± %s" % number(explain.get("combined_offset_ci95_counts"), "%.1f")))
    return rows


def pins_figure(points, fits, offset):
    scans = [int(s) for s in fits["scan"]]
    fig, ax = plt.subplots(figsize=(10, 3.4))
    mpc = offset["mm_per_count"][0]
    for k, s in enumerate(scans):
        sel = points["scan"] == s
        c, w = points["counts"][sel], points["width_mm"][sel]
        line, = ax.plot(c, w, ".", ms=3, label="scan %d" % s)
        c0, r = fits["center_counts"][k], fits["radius_mm"][k]
        if fits["ok"][k] == 1 and math.isfinite(c0) and math.isfinite(r):
            cc = np.linspace(c0 - r / mpc, c0 + r / mpc, 200)
            chord = 2 * np.sqrt(np.maximum(r * r - ((cc - c0) * mpc) ** 2, 0))
            near = np.abs(c - c0) * mpc < r
            base = np.median(w[near] - 2 * np.sqrt(np.maximum(r * r - ((c[near] - c0) * mpc) ** 2, 0))) if near.any() else 0
            ax.plot(cc, chord + base, "-", lw=0.8, color=line.get_color())
    if offset["ok"][0] == 1:
        o, ci = offset["offset_counts"][0], offset["ci95_counts"][0]
        ax.axvspan(o - ci, o + ci, color="#2ca02c", alpha=0.3, label="offset, 95 %% interval (%.2f ± %.2f counts)" % (o, ci))
        ax.axvline(offset["rig_offset_counts"][0], color="k", lw=0.8, ls="--", label="rig file's offset")
        lo = min(np.nanmin(fits["center_counts"]), o) - 3 * max(ci, 1)
        hi = max(np.nanmax(fits["center_counts"]), o) + 3 * max(ci, 1)
        span = max(hi - lo, 4 * np.nanmax(fits["radius_mm"]) / mpc)
        ax.set_xlim((lo + hi) / 2 - span / 2, (lo + hi) / 2 + span / 2)
    ax.set_xlabel("counts since the pin stood under the nozzle")
    ax.set_ylabel("chord width, mm")
    # Beside the axes: inside, it covers the chords' feet.
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0)
    return png(fig)


def explain_section(explain):
    """The model against the data, the effects, the residual and the offsets."""
    rows = [(e.get("name", e.get("effect", "?")), ", ".join("%s %.4g" % (k, v.get("value", math.nan)) if isinstance(v, dict)
             else "%s %s" % (k, v) for k, v in (e.get("parameters") or {}).items()),
             "%.2f" % e.get("fit_before_pct", math.nan), "%.2f" % e.get("fit_after_pct", math.nan))
            for e in explain.get("effects_added", [])]
    body = "<p>Model fit %.2f %% before, %.2f %% after; RMS %.4g before, %.4g after.</p>" % (
        explain.get("fit_before_pct", math.nan), explain.get("fit_after_pct", math.nan),
        explain.get("rms_before", math.nan), explain.get("rms_after", math.nan))
    body += table(["effect added", "parameters", "fit before, %", "fit after, %"], rows or [("none", "", "", "")])
    # The frequency and power tell apart two peaks that track the same
    # part (both within the run's frequency resolution of its rate).
    unexplained = [(u.get("what", ""), number(u.get("frequency_hz"), "%.4g"), u.get("tracks", ""),
                    number(u.get("power"), "%.3g")) for u in explain.get("unexplained", [])]
    if unexplained:
        body += "<h3>Unexplained</h3>" + table(["what", "frequency, Hz", "tracks", "power"], unexplained)
    if explain.get("compare"):
        body += "<h3>Model against the data</h3><p>The measured output and the model's, alone and with the " \
                "effects added (as MATLAB's compare).</p>" + compare_figure(explain["compare"], explain)
    if explain.get("diagnostics"):
        body += "<h3>Residual</h3><p>Its autocorrelation and its cross-correlation with the input, with " \
                "their 99 % bounds (as MATLAB's resid): a white residual independent of the input stays " \
                "inside.</p>" + resid_figure(explain["diagnostics"])
    if explain.get("spectrum"):
        body += "<h3>Residual spectrum</h3><p>On a log frequency axis; the unexplained peaks and the periodic " \
                "effects added are marked with what they track (the wheel's and the screw's rates where the " \
                "run has them).</p>" + spectrum_figure(explain["spectrum"], explain.get("unexplained", []),
                                                      explain.get("effects_added", []))
    offsets = offset_rows(explain)
    if offsets:
        body += "<h3>Encoder offset</h3>" + table(["source", "offset, counts", "95 % interval"], offsets)
    return '<section id="explain"><h2>Model and explain</h2>%s</section>' % body


def main(argv):
    if len(argv) < 3:
        sys.exit(__doc__)
    data, out_path = argv[1], argv[2]
    explain = None
    if "--explain" in argv:
        with open(argv[argv.index("--explain") + 1]) as f:
            explain = json.load(f)
    about = read_csv(os.path.join(data, "about.csv"))
    if about.get("kind", [""])[0] == "part":
        sections = part_report.sections(data)
        if explain is not None:
            sections.append(explain_section(explain))
        write_page(about["run"][0], sections, out_path)
        return
    g = read_csv(os.path.join(data, "geometry.csv"))
    flow = read_csv(os.path.join(data, "flow.csv"))
    lines, points = read_csv(os.path.join(data, "lines.csv")), read_csv(os.path.join(data, "profiles.csv"))
    pin_points, pin_fits = read_csv(os.path.join(data, "pin_points.csv")), read_csv(os.path.join(data, "pin_fits.csv"))
    pin_offset = read_csv(os.path.join(data, "pin_offset.csv"))
    run = about["run"][0]

    n = len(g["profile"])
    valid = int(np.sum(g["valid"] == 1))
    summary = [("run", run), ("rig file", about["rig"][0]), ("profiles", n),
               ("valid", "%d (%.1f %%)" % (valid, 100.0 * valid / max(n, 1)))]
    statuses = {}
    for s in g["status"]:
        statuses[s] = statuses.get(s, 0) + 1
    summary += [("invalid: " + s, c) for s, c in sorted(statuses.items()) if s != "valid"]
    if about["occlusion_line"][0]:
        summary.append(("occlusion", about["occlusion_line"][0]))
    if flow is not None:
        ok = flow["valid"] == 1
        t, q = flow["t_s"][ok], flow["flow_mm3_s"][ok]
        summary.append(("volume (trapezoids over extrusion time)", "%.1f mm³" % np.trapz(q, t) if len(t) > 1 else "-"))
    else:
        summary.append(("flow", "none: the archive has no encoder readings or log"))

    sections = ['<section id="summary"><h2>Summary</h2>%s</section>' % table(["", ""], summary)]
    sections.append('<section id="profiles"><h2>Profiles</h2><p>Five profiles across the run: the points, the '
                    'reference line fitted to the bare surface, the detection threshold above it, the edges, and the '
                    'measured area (shaded); the title gives the hidden share the occlusion correction removes.</p>%s'
                    '</section>' % profiles_figure(points, lines))
    sections.append('<section id="geometry"><h2>Area, width and height</h2><p>Against measurement time; invalid '
                    'profiles are marked at the bottom of each plot by why.</p>%s</section>' % geometry_figure(g))
    if flow is not None:
        sections.append('<section id="flow"><h2>Flow</h2><p>Q = v A in extrusion time (the time the material left '
                        'the nozzle), with its uncertainty band from the area.</p>%s</section>' % flow_figure(flow, explain))
    if explain is not None:
        sections.append(explain_section(explain))
    if pin_points is not None:
        o = pin_offset
        text = ("offset %.2f ± %.2f counts (95 %%), %d of %d scans used; the rig file says %.2f counts" %
                (o["offset_counts"][0], o["ci95_counts"][0], o["used"][0], o["total"][0], o["rig_offset_counts"][0])
                if o["ok"][0] == 1 else "no offset: %s" % o["reason"][0])
        sections.append('<section id="pins"><h2>Pin scans</h2><p>Each scan\'s chord widths of the pin against the '
                        'counts travelled, its fitted chord, and the offset with its interval: %s.</p>%s</section>'
                        % (html.escape(text), pins_figure(pin_points, pin_fits, o)))

    write_page(run, sections, out_path)

if __name__ == "__main__":
    try:
        main(sys.argv)
    except (OSError, ValueError, KeyError, TypeError) as e:  # one line, never a traceback
        sys.stderr.write("bead report: %s: %s\n" % (type(e).__name__, e))
        sys.exit(1)
