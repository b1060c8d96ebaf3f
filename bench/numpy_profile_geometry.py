#!/usr/bin/python3
"""The per-profile bead geometry as a NumPy user would write it: the
baseline libbead's benchmark compares itself with (same algorithm: median
start, inlier least squares, perpendicular heights between the areas,
largest run above the threshold, feet to the noise floor, trapezoid area, edge crossings).

Usage: numpy_profile_geometry.py DATA.f32 N_PROFILES N_POINTS
DATA holds the shared x grid [P] then z [N, P], float32. Prints profiles/s.
"""
import sys
import time

import numpy as np

LEFT, RIGHT = (-24.0, -12.0), (12.0, 24.0)


def reference_line(x, z):
    ok = np.isfinite(z)
    lm = ok & (x >= LEFT[0]) & (x <= LEFT[1])
    rm = ok & (x >= RIGHT[0]) & (x <= RIGHT[1])
    xl, zl, xr, zr = x[lm], z[lm], x[rm], z[rm]
    b = (np.median(zr) - np.median(zl)) / (np.median(xr) - np.median(xl))
    a = np.median(zl) - b * np.median(xl)
    xs, zs = np.concatenate([xl, xr]), np.concatenate([zl, zr])
    # one least-squares refit on the points within 3.5 robust sigmas
    r = zs - a - b * xs
    band = 3.5 * max(1.4826 * np.median(np.abs(r)), 0.002 * np.hypot(1, b))
    m = np.abs(r) <= band
    b, a = np.polyfit(xs[m], zs[m], 1)
    r = zs[m] - a - b * xs[m]
    return a, b, np.sqrt(np.mean(r ** 2) / (1 + b * b))


def geometry(x, z):
    a, b, rms = reference_line(x, z)
    # the bead is looked for between the areas, 16 points into each
    i0 = max(np.searchsorted(x, LEFT[1], side="right") - 16, 0)
    i1 = min(np.searchsorted(x, RIGHT[0]) + 16, len(x))
    x, z = x[i0:i1], z[i0:i1]
    ok = np.isfinite(z)
    x, z = x[ok], z[ok]
    norm = np.hypot(1.0, b)
    h = (z - a - b * x) / norm
    s = (x + b * (z - a)) / norm
    # spikes: off the median of five
    pad = np.pad(h, 2, mode="edge")
    med = np.median(np.lib.stride_tricks.sliding_window_view(pad, 5), axis=1)
    keep = np.abs(h - med) <= 0.5
    h, s, x = h[keep], s[keep], x[keep]
    above = h > max(0.05, 6 * rms)
    edges = np.flatnonzero(np.diff(np.concatenate([[0], above.astype(np.int8), [0]])))
    starts, ends = edges[::2], edges[1::2] - 1
    if len(starts) == 0:
        return np.nan, np.nan, np.nan
    pieces = 0.5 * (h[1:] + h[:-1]) * np.diff(s)
    csum = np.concatenate([[0], np.cumsum(pieces)])
    i = np.argmax(csum[ends] - csum[starts])
    lo, hi = starts[i], ends[i]
    floor = max(0.001, 2 * rms)
    while lo > 0 and h[lo - 1] > floor:
        lo -= 1
    while hi + 1 < len(h) and h[hi + 1] > floor:
        hi += 1
    lo, hi = lo - 1, hi + 1
    area = np.trapz(h[lo:hi + 1], s[lo:hi + 1])
    t_l = np.clip(-h[lo] / (h[lo + 1] - h[lo]), 0, 1)
    t_r = np.clip(-h[hi] / (h[hi - 1] - h[hi]), 0, 1)
    width = (s[hi] + t_r * (s[hi - 1] - s[hi])) - (s[lo] + t_l * (s[lo + 1] - s[lo]))
    height = np.max(np.median(np.lib.stride_tricks.sliding_window_view(h[lo:hi + 1], 3), axis=1))
    return area, width, height


def main():
    path, n, p = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
    data = np.fromfile(path, dtype=np.float32).astype(np.float64)
    x, z = data[:p], data[p:].reshape(n, p)
    geometry(x, z[0])  # warm-up
    start = time.perf_counter()
    done = 0
    while time.perf_counter() - start < 1.0 or done < n:
        geometry(x, z[done % n])
        done += 1
    print(done / (time.perf_counter() - start))


if __name__ == "__main__":
    main()
