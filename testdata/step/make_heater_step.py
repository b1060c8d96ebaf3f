#!/usr/bin/env python3
"""Writes heater_step.csv: a step test of seed 004's extruder heater, its
third-order model eq. 14, H(s) = 1.0033 / ((44.1315 s + 1)(2.0042 s + 1)
(1.9689 s + 1)) (the command in degrees C of set point, 218 C at 12 V in
the paper's Fig. 3), simulated exactly (zero-order hold at the 0.5 s
sample) from ambient 25 C, the command stepped 25 -> 218 C at t = 30 s,
430 s in all, with 0.3 C of white measurement noise (seeded). Needs
Debian's python3-numpy and python3-scipy:
    python3 testdata/step/make_heater_step.py > testdata/step/heater_step.csv
"""
import sys

import numpy as np
from scipy import signal

DT_S, DURATION_S, STEP_AT_S = 0.5, 430.0, 30.0
AMBIENT_C, SET_POINT_C, NOISE_C = 25.0, 218.0, 0.3
GAIN, TAUS_S = 1.0033, (44.1315, 2.0042, 1.9689)  # seed 004, eq. (14)

den = np.poly1d([1.0])
for tau in TAUS_S:
    den *= np.poly1d([tau, 1.0])
t = np.arange(0.0, DURATION_S + DT_S / 2, DT_S)
cmd = np.where(t >= STEP_AT_S, SET_POINT_C, AMBIENT_C)
# Deviations from ambient (the heater at rest holds ambient), held between samples.
plant = signal.cont2discrete(signal.tf2ss([GAIN], den.coeffs), DT_S, method="zoh")
_, dev, _ = signal.dlsim(plant, cmd - AMBIENT_C)
temp = AMBIENT_C + dev[:, 0] + np.random.default_rng(4).normal(0.0, NOISE_C, t.size)
out = sys.stdout
out.write("t_s,heater_cmd_c,temp_c\n")
for row in zip(t, cmd, temp):
    out.write("%.1f,%.1f,%.3f\n" % row)
