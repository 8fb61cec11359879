#!/usr/bin/env python3
"""Test of scripts/coast-regression.py (docs/PERFORMANCE.md "Held-out losses: the track says coast
further").

  coast_regression_test.py PREDVS WORKDIR

GIVEN a noise-free 60 Hz track whose u channel is a ramp and whose v channel a zigzag flipping every
20 frames, and forecasts that extrapolate the true velocity over 2 frames, WHEN coast-regression.py
regresses the measured displacements on the default coast's, THEN on the ramp the factor at each lag
is u / C(u) (a ramp goes on where the coast slows down; C from an independent Simpson rule), on the
zigzag it is 0 at a full period (every displacement over it is 0), and a predictor that is not in
the file or a lag of 0 frames is refused in one line with a non-zero exit.
"""
import math
import os
import sys

from script_test import arguments, checked, finish, refused_in_one_line, run, script

SCRIPT = script("coast-regression.py")
RATE_HZ = 60.0
FRAMES = 600
HALF_PERIOD = 20  # frames per zigzag leg


def coast_time(u, tau=0.2, shape=1.5, n=2000):
    """The integral over [0, u] of exp(-(s / tau)^shape) ds, Simpson's rule (n even)."""
    h = u / n
    f = lambda s: math.exp(-((s / tau) ** shape))
    return h / 3.0 * (f(0.0) + f(u) + sum((4 if i % 2 else 2) * f(i * h) for i in range(1, n)))


def write_files(work):
    dt = 1.0 / RATE_HZ
    horizon = 2 * dt
    u = lambda t: 100.0 * t
    vel_v = lambda k: 120.0 if (k // HALF_PERIOD) % 2 == 0 else -120.0
    v = [0.0]
    for k in range(1, FRAMES + 2):
        v.append(v[-1] + vel_v(k - 1) * dt)
    track, pred = os.path.join(work, "t.csv"), os.path.join(work, "p.csv")
    with open(track, "w") as f:
        f.write("t,u,v,u_true,v_true\n")
        for k in range(FRAMES):
            t = k * dt
            f.write(f"{t!r},{u(t)!r},{v[k]!r},{u(t)!r},{v[k]!r}\n")
    with open(pred, "w") as f:
        f.write("t,u,v,t_target,cv.u_pred,cv.v_pred\n")
        for k in range(FRAMES):
            t = k * dt
            f.write(f"{t!r},{u(t)!r},{v[k]!r},{t + horizon!r},{u(t) + 100.0 * horizon!r},{v[k] + vel_v(k) * horizon!r}\n")
    return track, pred


def main():
    _, work = arguments()
    track, pred = write_files(work)
    lags = (6, 12, 2 * HALF_PERIOD)
    r = checked([sys.executable, SCRIPT, track, pred, "--predictor", "cv", "--lags", ",".join(map(str, lags))])
    rows = {int(f[0]): [float(x) for x in f[1:]] for f in (l.split() for l in r.stdout.strip().split("\n")[2:])}
    failures = []
    for m in lags:
        uu = m / RATE_HZ
        want = uu / coast_time(uu)
        w_u, w_v = rows[m][3], rows[m][4]
        if abs(w_u / want - 1.0) > 0.01:
            failures.append(f"lag {m}: ramp factor {w_u}, expected u / C(u) = {want:.4f}")
    if abs(rows[2 * HALF_PERIOD][4]) > 0.005:
        failures.append(f"lag {2 * HALF_PERIOD}: zigzag factor {rows[2 * HALF_PERIOD][4]} over a full period, expected 0")
    for bad in (["--predictor", "kf-ca"], ["--predictor", "cv", "--lags", "0"]):
        r = run([sys.executable, SCRIPT, track, pred] + bad)
        if not refused_in_one_line(r):
            failures.append(f"{' '.join(bad)} not refused in one line: exit {r.returncode}, {r.stderr!r}")
    finish(failures, "coast-regression: " + "; ".join(f"lag {m}: {rows[m][3]:.3f} / {rows[m][4]:.3f}" for m in lags))


if __name__ == "__main__":
    main()
