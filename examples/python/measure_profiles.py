#!/usr/bin/env python3
"""Measures every profile of a profiles CSV (profile,t_s,encoder,x_mm,z_mm,
one row per point, a profile's rows together; an empty z is a dropout)
through libbead's C interface with ctypes, and prints a row per profile:
    profile,area_mm2,width_mm,height_mm,center_x_mm,valid,status

    measure_profiles.py LEFT_MIN LEFT_MAX RIGHT_MIN RIGHT_MAX profiles.csv

libbead.so is found by the BEAD_LIBRARY environment variable (a path), else
on the loader's search path (ctypes.util.find_library("bead")).
"""
import csv
import ctypes
import ctypes.util
import math
import os
import sys


class Geometry(ctypes.Structure):
    # bead_geometry of bead/bead.h, field for field.
    _fields_ = [
        ("area_mm2", ctypes.c_double),
        ("area_sigma_mm2", ctypes.c_double),
        ("width_mm", ctypes.c_double),
        ("height_mm", ctypes.c_double),
        ("center_x_mm", ctypes.c_double),
        ("left_edge_x_mm", ctypes.c_double),
        ("right_edge_x_mm", ctypes.c_double),
        ("threshold_mm", ctypes.c_double),
        ("reference_rms_mm", ctypes.c_double),
        ("reference_points", ctypes.c_int32),
        ("bead_points", ctypes.c_int32),
        ("dropped_points", ctypes.c_int32),
        ("valid", ctypes.c_int32),
        ("status", ctypes.c_int32),
    ]


def load():
    path = os.environ.get("BEAD_LIBRARY") or ctypes.util.find_library("bead")
    if not path:
        sys.exit("libbead.so not found: set BEAD_LIBRARY to its path")
    lib = ctypes.CDLL(path)
    pair = ctypes.c_double * 2
    lib.bead_processor_create.argtypes = [pair, pair]
    lib.bead_processor_create.restype = ctypes.c_void_p
    lib.bead_processor_measure.argtypes = [ctypes.c_void_p, ctypes.POINTER(ctypes.c_float),
                                           ctypes.POINTER(ctypes.c_float), ctypes.c_size_t,
                                           ctypes.POINTER(Geometry)]
    lib.bead_processor_measure.restype = ctypes.c_int
    lib.bead_processor_destroy.argtypes = [ctypes.c_void_p]
    lib.bead_last_error.restype = ctypes.c_char_p
    lib.bead_status_name.argtypes = [ctypes.c_int32]
    lib.bead_status_name.restype = ctypes.c_char_p
    return lib, pair


def main(argv):
    if len(argv) != 6:
        sys.exit(__doc__)
    lib, pair = load()
    left = pair(float(argv[1]), float(argv[2]))
    right = pair(float(argv[3]), float(argv[4]))
    processor = lib.bead_processor_create(left, right)
    if not processor:
        sys.exit(lib.bead_last_error().decode())
    geometry = Geometry()
    out = csv.writer(sys.stdout, lineterminator="\n")
    out.writerow(["profile", "area_mm2", "width_mm", "height_mm", "center_x_mm", "valid", "status"])

    def flush(profile, xs, zs):
        n = len(xs)
        x = (ctypes.c_float * n)(*xs)
        z = (ctypes.c_float * n)(*zs)
        if lib.bead_processor_measure(processor, x, z, n, ctypes.byref(geometry)) != 0:
            sys.exit(f"profile {profile}: {lib.bead_last_error().decode()}")
        g = geometry
        out.writerow([profile] + [f"{v:.9g}" for v in (g.area_mm2, g.width_mm, g.height_mm, g.center_x_mm)] +
                     [g.valid, lib.bead_status_name(g.status).decode()])

    with open(argv[5], newline="") as f:
        rows = csv.reader(f)
        header = next(rows)
        if header[:5] != ["profile", "t_s", "encoder", "x_mm", "z_mm"]:
            sys.exit(f"{argv[5]}: line 1: expected profile,t_s,encoder,x_mm,z_mm")
        current, xs, zs = None, [], []
        for row in rows:
            profile = int(row[0])
            if profile != current and current is not None:
                flush(current, xs, zs)
                xs, zs = [], []
            current = profile
            xs.append(float(row[3]) if row[3] else math.nan)
            zs.append(float(row[4]) if row[4] else math.nan)
        if current is not None:
            flush(current, xs, zs)
    lib.bead_processor_destroy(processor)


if __name__ == "__main__":
    main(sys.argv)
