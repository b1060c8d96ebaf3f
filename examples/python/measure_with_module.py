#!/usr/bin/env python3
"""A run measured and its flow computed with `import bead` (the module
built with libbead: python/; PYTHONPATH names its folder when it is not
installed), NumPy arrays in and out.

    python3 measure_with_module.py RIG.yaml RUN.h5

Prints the run's size, each bead's mean geometry and the volume. For those
who cannot build the module, measure_profiles.py does the per-profile part
through libbead's C interface (ctypes)."""
import sys

import numpy as np

import bead


def main(rig, run):
    r = bead.read_run(run)  # arrays: t_s [N] s, x_mm, z_mm [N, P] mm, log
    print("%s: %d profiles of %d points" % (run, r["z_mm"].shape[0], r["z_mm"].shape[1]))
    g = bead.measure_run(rig, run)  # as `bead measure`: the geometry CSV's columns
    ok = g["valid"]
    print("valid %d; mean area %.4f mm^2 (corrected %.4f), width %.3f mm, height %.3f mm" %
          (ok.sum(), np.mean(g["area_mm2"][ok]), np.mean(g["area_corrected_mm2"][ok]), np.mean(g["width_mm"][ok]),
           np.mean(g["height_mm"][ok])))
    f = bead.flow(rig, run)  # as `bead flow`: Q = v A in extrusion time
    print("volume %.1f mm^3" % f["total_volume_mm3"])


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    try:
        main(sys.argv[1], sys.argv[2])
    except bead.Error as e:
        sys.exit("error: %s" % e)
