#!/usr/bin/python3
# The innovations of a constant-velocity Kalman filter (kf-cv's model) on a target moving on a line
# under white measurement noise, in the steady state, for several process-noise densities q and
# assumed measurement variances R_f (the truth: 1 px^2): the spread E[eps^2 / S] that covariance
# matching balances at 1, and the lag-one correlation that the whitening balances at 0
# (process_noise_adapt.h; docs/PERFORMANCE.md "Innovations made white"). Exact, from the Riccati
# and Lyapunov equations of the filter's error; no simulation.
#   scripts/innovation-statistics.py [RATE_HZ]   (default 25)
import sys

import numpy as np

rate = float(sys.argv[1]) if len(sys.argv) > 1 else 25.0
T = 1.0 / rate
F = np.array([[1.0, T], [0.0, 1.0]])
H = np.array([[1.0, 0.0]])


def steady(q, r_f):
    Q = q * np.array([[T**3 / 3, T**2 / 2], [T**2 / 2, T]])
    P = np.eye(2) * 100.0
    for _ in range(5000):
        Pm = F @ P @ F.T + Q
        S = (H @ Pm @ H.T)[0, 0] + r_f
        K = Pm @ H.T / S
        P = (np.eye(2) - K @ H) @ Pm
    # prior error e(k+1) = F (I - K H) e(k) - F K n(k), n ~ N(0, 1) (the true noise; no process noise)
    A, B = F @ (np.eye(2) - K @ H), -F @ K
    C = np.zeros((2, 2))
    for _ in range(20000):
        C = A @ C @ A.T + B @ B.T
    c0 = (H @ C @ H.T)[0, 0] + 1.0
    c1 = (H @ A @ C @ H.T)[0, 0] + (H @ B)[0, 0]
    return c0 / S, c1 / c0, np.sqrt(C[1, 1])


print(f"CV filter at {rate:g} Hz, a line under 1 px of noise: spread E[eps^2/S] / lag-one correlation / velocity noise [px/s]")
for r_f in (0.57, 0.8, 1.0, 1.5):
    cells = []
    for q in (1e1, 1e2, 1e3, 1e4, 3e4, 1e5):
        spread, rho, v = steady(q, r_f)
        cells.append(f"q {q:.0e}: {spread:5.2f} {rho:+.2f} {v:5.1f}")
    print(f"R_f {r_f:4.2f} | " + " | ".join(cells))
