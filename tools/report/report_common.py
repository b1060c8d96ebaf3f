"""What bead report's pages share: reading the command's CSVs, pictures as
embedded PNG, tables, and the page written atomically."""
import base64
import csv
import html
import io
import math
import os
import tempfile

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def read_csv(path):
    """Columns by name: floats where they parse (empty: NaN), else text."""
    if not os.path.exists(path):
        return None
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    cols = {}
    for key in (rows[0].keys() if rows else []):
        values = [r[key] for r in rows]
        try:
            cols[key] = np.array([float(v) if v not in ("", "nan") else math.nan for v in values])
        except ValueError:
            cols[key] = values
    return cols


def png(fig):
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=110, bbox_inches="tight")
    plt.close(fig)
    return '<img alt="" src="data:image/png;base64,%s">' % base64.b64encode(buf.getvalue()).decode()


def number(value, form):
    """A JSON number as text; empty where there is none."""
    return form % value if isinstance(value, (int, float)) and math.isfinite(value) else ""


def table(header, rows):
    out = "<table>"
    if any(header):
        out += "<tr>" + "".join("<th>%s</th>" % html.escape(h) for h in header) + "</tr>"
    for r in rows:
        out += "<tr>" + "".join("<td>%s</td>" % html.escape(str(v)) for v in r) + "</tr>"
    return out + "</table>"


def write_page(run, sections, out_path):
    """The page: one file, pictures inside it, no link outside; atomically."""
    page = """<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8"><title>bead report: %s</title>
<style>body{font-family:sans-serif;max-width:1150px;margin:1em auto;padding:0 1em;color:#222}
h1{font-size:1.4em}h2{font-size:1.15em;border-bottom:1px solid #ccc;padding-bottom:.2em}
table{border-collapse:collapse;font-size:.9em}td,th{border:1px solid #ddd;padding:.2em .6em;text-align:left}
img{max-width:100%%}p{font-size:.92em}</style></head>
<body><h1>bead report: %s</h1>
%s
<footer><p>Drawn by libbead's bead report; units mm, s, mm², mm³/s.</p></footer>
</body></html>
""" % (html.escape(os.path.basename(run)), html.escape(run), "\n".join(sections))
    folder = os.path.dirname(os.path.abspath(out_path))
    fd, tmp = tempfile.mkstemp(dir=folder, prefix=".bead-report-")
    with os.fdopen(fd, "w") as f:
        f.write(page)
    os.chmod(tmp, 0o644)
    os.replace(tmp, out_path)

