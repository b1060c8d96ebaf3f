"""bead.measure on the sample run's block repeated N times, one thread:
prints the best of its repetitions' rates (argv[3], 30 when not given) (profiles/s). Run by bench_numpy_block."""
import sys
import time

import numpy as np

import bead

r = bead.read_run(sys.argv[1])
z = np.ascontiguousarray(np.tile(r["z_mm"], (int(sys.argv[2]), 1)))
x = r["x_mm"] if r["x_mm"].ndim == 1 else np.ascontiguousarray(r["x_mm"][0])  # as the C++ side: the first x for all
best = 0.0
for _ in range(int(sys.argv[3]) if len(sys.argv) > 3 else 30):
    start = time.perf_counter()
    bead.measure(x, z, [[-24, -12], [12, 24]], threads=1)
    best = max(best, z.shape[0] / (time.perf_counter() - start))
print(best)
