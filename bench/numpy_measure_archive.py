#!/usr/bin/python3
"""End to end as a NumPy user would do it: read a run archive with h5py,
measure every profile with numpy_profile_geometry.geometry (the same
algorithm as libbead's), write a CSV of area, width and height. The
baseline of bench/archive_bench.py on a small archive.

Usage: numpy_measure_archive.py RUN.h5 OUT.csv
"""
import os
import sys

import h5py
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from numpy_profile_geometry import geometry  # noqa: E402


def main():
    path, out = sys.argv[1], sys.argv[2]
    with h5py.File(path, "r") as f:
        t = f["/profiles/t_s"][...]
        x = f["/profiles/x_mm"][...].astype(np.float64)
        z = f["/profiles/z_mm"][...].astype(np.float64)
    rows = []
    for i in range(len(t)):
        xi = x[i] if x.ndim == 2 else x
        keep = np.isfinite(xi)  # a fan sensor reports x = NaN where it saw nothing
        try:
            area, width, height = geometry(xi[keep], z[i][keep])
        except (ValueError, IndexError, TypeError, np.linalg.LinAlgError):
            area = width = height = np.nan
        rows.append((i, t[i], area, width, height))
    np.savetxt(out, np.array(rows), delimiter=",", header="profile,t_s,area_mm2,width_mm,height_mm", comments="")


if __name__ == "__main__":
    main()
