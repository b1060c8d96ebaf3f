"""The sections of `bead report`'s page on a part scan (format 1.1).

DATA_DIR holds about.csv (kind part), part_geometry.csv, layers.csv and
sections.csv, and part_flow.csv where the scan has a log (written by
`bead report`; the geometry and flow CSVs are what `bead measure` and
`bead flow` write on the scan).
"""
import math
import os

import matplotlib.pyplot as plt
import numpy as np

from report_common import png, read_csv, table


def layer_colours(layers):
    """One colour per layer, bottom to top."""
    cmap = plt.get_cmap("viridis")
    top = max(max(layers), 1)
    return {int(l): cmap(0.9 * l / top) for l in layers}


def sections_figure(sec, colours):
    """Each place's cross-sections, every layer's surface stacked in the bed frame."""
    places = sorted(set(int(s) for s in sec["section"]))
    fig, axes = plt.subplots(1, len(places), figsize=(3.8 * len(places), 3.6), squeeze=False)
    for ax, k in zip(axes[0], places):
        at = sec["section"] == k
        for layer in sorted(set(int(l) for l in sec["layer"][at])):
            sel = at & (sec["layer"] == layer)
            ax.plot(sec["x_mm"][sel], sec["z_mm"][sel], ".", ms=1.5, color=colours.get(layer, "k"),
                    label="layer %d" % layer)
        # The wall and twice its width either side of it (the bare bed beyond says nothing).
        z, x = sec["z_mm"][at], sec["x_mm"][at]
        up = x[z > z.min() + 0.1 * (z.max() - z.min())] if z.max() > z.min() else x
        if len(up):
            half = max(up.max() - up.min(), 1.0)
            ax.set_xlim(up.min() - half, up.max() + half)
        ax.set_title("path %.1f mm" % sec["place_mm"][at][0], fontsize=9)
        ax.set_xlabel("x across the path, mm (bed frame)")
        ax.set_aspect("equal", adjustable="datalim")
    axes[0][0].set_ylabel("z above the bed, mm")
    axes[0][0].legend(fontsize=7, markerscale=4)
    fig.tight_layout()
    return png(fig)


def along_path_figure(g, colours):
    """Area seen and corrected, layer height and the wall's wander along the path."""
    fig, axes = plt.subplots(3, 1, figsize=(10, 7.5), sharex=True)
    ok = g["valid"] == 1
    for layer in sorted(colours):
        sel = ok & (g["layer"] == layer)
        c = colours[layer]
        axes[0].plot(g["path_mm"][sel], g["area_mm2"][sel], "-", lw=0.6, color=c, alpha=0.45)
        axes[0].plot(g["path_mm"][sel], g["area_corrected_mm2"][sel], "-", lw=1.0, color=c, label="layer %d" % layer)
        axes[1].plot(g["path_mm"][sel], g["height_mm"][sel], "-", lw=0.9, color=c)
        if "offset_below_mm" in g:
            axes[2].plot(g["path_mm"][sel], g["offset_below_mm"][sel], "-", lw=0.9, color=c)
    axes[0].set_ylabel("area, mm²")
    axes[0].set_title("thin: as seen; thick: less the groove hidden under the overhangs", fontsize=9)
    axes[0].legend(fontsize=7, ncol=6)
    axes[1].set_ylabel("layer height, mm")
    axes[2].set_ylabel("centre over the bead below, mm")
    axes[2].set_xlabel("path, mm")
    fig.tight_layout()
    return png(fig)


def speed_figure(f, colours):
    """Flow and area against the head's speed: where the head slows with the
    extruder unchanged, the area grows (the corner bulge)."""
    fig, axes = plt.subplots(1, 2, figsize=(10, 3.8))
    ok = f["valid"] == 1
    for layer in sorted(colours):
        sel = ok & (f["layer"] == layer)
        area = np.where(np.isnan(f["area_corrected_mm2"]), f["area_mm2"], f["area_corrected_mm2"])
        axes[0].plot(f["head_speed_mm_s"][sel], f["flow_mm3_s"][sel], ".", ms=2, color=colours[layer],
                     label="layer %d" % layer)
        axes[1].plot(f["head_speed_mm_s"][sel], area[sel], ".", ms=2, color=colours[layer])
    axes[0].set_xlabel("head speed, mm/s")
    axes[0].set_ylabel("flow Q = v A, mm³/s")
    axes[1].set_xlabel("head speed, mm/s")
    axes[1].set_ylabel("area, mm²")
    axes[0].legend(fontsize=7, markerscale=4)
    fig.tight_layout()
    return png(fig)


def cell(v, form):
    """A table cell: the number in `form`, "-" where there is none."""
    return form % v if isinstance(v, float) and math.isfinite(v) else "-"


def summary_rows(about, g, f):
    n = len(g["profile"]) if g is not None else 0
    valid = int(np.sum(g["valid"] == 1)) if n else 0
    rows = [("part scan", about["run"][0]), ("rig file", about["rig"][0]), ("profiles", n),
            ("valid", "%d (%.1f %%)" % (valid, 100.0 * valid / max(n, 1)))]
    statuses = {}
    for s in (g["status"] if n else []):
        statuses[s] = statuses.get(s, 0) + 1
    rows += [("invalid: " + s, c) for s, c in sorted(statuses.items()) if s != "valid"]
    if f is None:
        rows.append(("flow", "none: the scan has no /log (the nozzle's place and time)"))
        return rows
    rows.append(("volume laid (area integrated along the path)", cell(about["total_volume_mm3"][0], "%.1f mm³")))
    if about["unplaced"][0] > 0:
        rows.append(("profiles the log never had the nozzle pass", int(about["unplaced"][0])))
    slow = about["slow_profiles"][0]
    if slow > 0:
        rows.append(("where the head slowed below 90 % of its median speed",
                     "%d profiles, %.1f against %.1f mm/s: area %+.1f %%, flow %+.1f %% over the rest" %
                     (slow, about["slow_speed_mm_s"][0], about["rest_speed_mm_s"][0],
                      100 * about["slow_area_excess"][0], 100 * about["slow_flow_excess"][0])))
    return rows


def layer_rows(layers, g):
    rows = []
    for k, layer in enumerate(layers["layer"]):
        sel = (g["layer"] == layer) & (g["valid"] == 1)
        height = np.median(g["height_mm"][sel]) if np.any(sel) else math.nan
        rows.append((int(layer), int(layers["profiles"][k]), int(layers["valid"][k]),
                     cell(layers["mean_area_mm2"][k], "%.3f"), cell(layers["mean_area_corrected_mm2"][k], "%.3f"),
                     cell(float(height), "%.3f"), cell(layers["shift_mm"][k], "%+.3f"),
                     cell(layers["volume_mm3"][k], "%.1f")))
    return rows


def missing_below(layers):
    """Why a layer has nothing measured: the layer below not scanned."""
    words = ["layer %d: layer %d is not in the scan, nothing to measure it against" % (l, l - 1)
             for l, n, none in zip(layers["layer"].astype(int), layers["profiles"], layers["no_surface_below"])
             if l > 0 and n == none]
    return "".join("<p>%s.</p>" % w for w in words)


def sections(data):
    """The page's sections, in order."""
    about = read_csv(os.path.join(data, "about.csv"))
    g = read_csv(os.path.join(data, "part_geometry.csv"))
    f = read_csv(os.path.join(data, "part_flow.csv"))
    layers = read_csv(os.path.join(data, "layers.csv"))
    sec = read_csv(os.path.join(data, "sections.csv"))
    out = ['<section id="summary"><h2>Summary</h2>%s</section>' % table(["", ""], summary_rows(about, g, f))]
    if layers is None or not len(layers.get("layer", [])):
        out.append("<p>No layer in the scan: nothing to draw.</p>")
        return out
    colours = layer_colours([int(l) for l in layers["layer"]])
    out.append('<section id="layers"><h2>Layers</h2><p>Each layer against the one below (layer 0 on the bed): the '
               'mean area seen and less the groove its bead hides, the median layer height (the gain at the crest), '
               'the lateral shift between the passes, and the volume along the path.</p>%s%s</section>' %
               (table(["layer", "profiles", "valid", "area seen, mm²", "area corrected, mm²", "height, mm",
                       "pass shift, mm", "volume, mm³"], layer_rows(layers, g)), missing_below(layers)))
    if sec is not None and len(sec.get("section", [])):
        out.append('<section id="sections"><h2>Cross-sections</h2><p>Every layer\'s scanned surface at three places '
                   'along the path (each layer\'s profile nearest the place, within 5 mm), in the bed frame: the '
                   'wall as it grew.</p>%s</section>' % sections_figure(sec, colours))
    if np.any(g["valid"] == 1):
        out.append('<section id="path"><h2>Along the path</h2><p>Each layer\'s valid profiles.</p>%s</section>' %
                   along_path_figure(g, colours))
    else:
        out.append('<section id="path"><h2>Along the path</h2><p>No valid profile: nothing measured to draw along '
                   'the path (the summary counts the profiles by why).</p></section>')
    if f is not None and np.any(f["valid"] == 1):
        out.append('<section id="speed"><h2>Flow and the head\'s speed</h2><p>Q = v<sub>head</sub> A at each '
                   'place, against the head\'s speed there.</p>%s</section>' % speed_figure(f, colours))
    return out
