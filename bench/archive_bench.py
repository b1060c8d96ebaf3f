#!/usr/bin/python3
"""Whole archives, end to end (issue: scan archives at scale). In one run:

  read floor   h5py reading /profiles (t_s, encoder, x_mm, z_mm) of a
               10-minute archive (120001 x 640) in one thread
  bead measure the same archive end to end (read, geometry, occlusion, CSV):
               its time against the read floor (target <= 0.75x) and its
               peak memory; the same for a 60-minute archive (--sixty):
               flat memory means the same peak; bead flow's time and peak
               on both (streamed too: a 56-byte row per profile goes to a
               scratch file, not memory)
  small        a 12000 x 128 archive: bead measure against a NumPy script
               doing the same geometry end to end (target >= 20x)
  start        bead --help and bead measure --help (process start alone),
               bead measure on a 2-second archive with --occlusion none and
               pooled (the fit's module loaded)
  baseline     with --baseline BEAD, another build's flow and start times
               beside ours, in the same run

Archives are made with `bead simulate` (and the 60-minute one by repeating
the 10-minute one six times, time and encoder running on) into --work,
and reused when they are there. Needs python3-h5py and python3-numpy.

Usage: archive_bench.py --bead build/tools/bead [--work /tmp/bead-bench] [--sixty] [--baseline OTHER/bead]
"""
import argparse
import filecmp
import os
import subprocess
import sys
import time

import h5py

HERE = os.path.dirname(os.path.abspath(__file__))


def simulate(bead, work, name, seconds, points):
    run = os.path.join(work, name, "run.h5")
    if os.path.exists(run):
        return run
    cfg = os.path.join(work, name + ".yaml")
    with open(cfg, "w") as f:
        f.write(f"seed: 7\nduration_s: {seconds}\nsensor: {{points: {points}}}\npins: {{scans: 1}}\n"
                "extruder:\n  command: {kind: steps, levels_v: [3.0, 4.0, 2.5, 3.5], "
                f"durations_s: [{seconds / 4}, {seconds / 4}, {seconds / 4}, {seconds / 4}], start_s: 0.3}}\n")
    subprocess.run([bead, "simulate", cfg, "-o", os.path.join(work, name)], check=True, stdout=subprocess.DEVNULL)
    return run


def repeat(src, dst, times):
    """dst: src's profiles and log `times` over, time and encoder running on."""
    if os.path.exists(dst):
        return dst
    os.makedirs(os.path.dirname(dst), exist_ok=True)
    tmp = dst + ".part"
    with h5py.File(src, "r") as a, h5py.File(tmp, "w") as b:
        for group, names in (("profiles", ("t_s", "encoder", "x_mm", "z_mm")),
                             ("log", ("t_s", "encoder", "screw_rpm", "extruder_cmd_v", "wheel_cmd_v"))):
            if group not in a:
                continue
            g = a[group]
            span = g["t_s"][-1] - g["t_s"][0] + (g["t_s"][1] - g["t_s"][0])
            turn = int(g["encoder"][-1] - g["encoder"][0])
            for name in names:
                if name not in g:
                    continue
                d = g[name]
                n = d.shape[0]
                if d.ndim == 1 and name == "x_mm":
                    b.create_dataset(f"{group}/{name}", data=d[...])
                    continue
                shape = (n * times,) + d.shape[1:]
                out = b.create_dataset(f"{group}/{name}", shape=shape, dtype=d.dtype, chunks=d.chunks,
                                       compression="gzip" if d.compression else None,
                                       compression_opts=4 if d.compression else None, shuffle=d.shuffle)
                step = 8192
                for k in range(times):
                    for i in range(0, n, step):
                        block = d[i:i + step]
                        if name == "t_s":
                            block = block + k * span
                        elif name == "encoder":
                            block = block + k * turn
                        out[k * n + i:k * n + i + len(block)] = block
    os.replace(tmp, dst)
    return dst


def run_timed(cmd):
    """Wall seconds and peak resident memory (MB) of one process."""
    start = time.perf_counter()
    proc = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    _, status, usage = os.wait4(proc.pid, 0)
    seconds = time.perf_counter() - start
    if status != 0:
        sys.exit(f"failed: {' '.join(cmd)}: {proc.stderr.read().decode()}")
    return seconds, usage.ru_maxrss / 1024.0


READ = """
import sys, time, h5py
start = time.perf_counter()
with h5py.File(sys.argv[1], "r") as f:
    for name in ("t_s", "encoder", "x_mm", "z_mm"):
        f["/profiles/" + name][...]
print(time.perf_counter() - start)
"""


def read_floor(path):
    """h5py reading the profiles in one thread, in its own process (a child
    forked from a Python that had held the arrays would carry their memory
    into the next child's peak)."""
    out = subprocess.run([sys.executable, "-c", READ, path], check=True, capture_output=True, text=True)
    return float(out.stdout)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--bead", required=True)
    ap.add_argument("--work", default="/tmp/bead-bench")
    ap.add_argument("--sixty", action="store_true", help="also the 60-minute archive (about 1.8 GB)")
    ap.add_argument("--baseline", help="another build's bead: its flow and start times printed beside ours")
    ap.add_argument("--repeat", nargs=3, metavar=("SRC", "DST", "TIMES"), help=argparse.SUPPRESS)
    a = ap.parse_args()
    if a.repeat:
        repeat(a.repeat[0], a.repeat[1], int(a.repeat[2]))
        return
    os.makedirs(a.work, exist_ok=True)
    ten = simulate(a.bead, a.work, "ten", 600, 640)
    rig = os.path.join(a.work, "ten", "rig.yaml")
    small = simulate(a.bead, a.work, "small", 60, 128)
    out = os.path.join(a.work, "geometry.csv")

    floor = read_floor(ten)
    bead_s, bead_mb = run_timed([a.bead, "measure", "--rig", rig, ten, "-o", out])
    print(f"10-minute archive (120001 x 640): h5py read {floor:.2f} s (one thread); "
          f"bead measure {bead_s:.2f} s = {bead_s / floor:.2f}x the read (target <= 0.75x), peak {bead_mb:.0f} MB")
    if a.sixty:
        # Made in a child: a process forked from a Python that had held the
        # blocks reports that Python's peak as its own (ru_maxrss survives exec).
        sixty = os.path.join(a.work, "sixty", "run.h5")
        subprocess.run([sys.executable, os.path.abspath(__file__), "--bead", a.bead, "--repeat", ten, sixty, "6"],
                       check=True)
        s, mb = run_timed([a.bead, "measure", "--rig", rig, sixty, "-o", out])
        print(f"60-minute archive (720006 x 640): bead measure {s:.2f} s, peak {mb:.0f} MB "
              f"({mb / bead_mb:.2f}x the 10-minute peak)")
    flow_out = os.path.join(a.work, "flow.csv")
    for name, path in (("10", ten),) + ((("60", sixty),) if a.sixty else ()):
        s, mb = run_timed([a.bead, "flow", "--rig", rig, path, "-o", flow_out])
        line = f"{name}-minute archive: bead flow {s:.2f} s, peak {mb:.0f} MB"
        if a.baseline:
            bs, bmb = run_timed([a.baseline, "flow", "--rig", rig, path, "-o", flow_out + ".baseline"])
            same = filecmp.cmp(flow_out, flow_out + ".baseline", shallow=False)
            line += f"; baseline {bs:.2f} s, peak {bmb:.0f} MB; CSVs {'identical' if same else 'DIFFER'}"
        print(line)

    small_rig = os.path.join(a.work, "small", "rig.yaml")
    # Best of several: one process's time on a shared machine moves by tens of per cent.
    bead_small = min(run_timed([a.bead, "measure", "--rig", small_rig, small, "-o", out])[0] for _ in range(5))
    numpy_small = min(run_timed([sys.executable, os.path.join(HERE, "numpy_measure_archive.py"), small,
                                 os.path.join(a.work, "numpy.csv")])[0] for _ in range(3))
    print(f"small archive (12001 x 128): bead measure {bead_small:.3f} s (best of 5), NumPy script "
          f"{numpy_small:.2f} s (best of 3): {numpy_small / bead_small:.0f}x (target >= 20x)")

    # Start: the programs alone, then a small archive end to end without and
    # with the occlusion fit (loaded on demand, tools/occlusion_module.h).
    tiny = simulate(a.bead, a.work, "tiny", 2, 128)
    tiny_rig = os.path.join(a.work, "tiny", "rig.yaml")
    starts = (["--help"], ["measure", "--help"],
              ["measure", "--rig", tiny_rig, tiny, "-o", out, "--occlusion", "none"],
              ["measure", "--rig", tiny_rig, tiny, "-o", out])
    for args in starts:
        line = f"start: bead {' '.join(os.path.basename(c) for c in args)}: "
        for label, bead in (("", a.bead),) + ((("baseline ", a.baseline),) if a.baseline else ()):
            best = min(run_timed([bead] + args)[0] for _ in range(20))
            line += f"{label}{1000 * best:.1f} ms  "
        print(line + "(best of 20)")


if __name__ == "__main__":
    main()
