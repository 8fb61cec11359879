#!/usr/bin/env python3
"""predvs — how far a track's own motion says a gap should be coasted (docs/PERFORMANCE.md,
"Held-out losses: the track says coast further").

    scripts/coast-regression.py TRACK.csv PREDICTIONS.csv --predictor NAME [--lags 2,6,12,18,24,32]

TRACK.csv is a one-point track (`predvs make-track`: t, u, v, ...), PREDICTIONS.csv the
predictions.csv that `predvs predict --input TRACK.csv --delay-frames H` wrote for it with NAME among
its predictors. On every measured frame k, the predictor's extrapolation rate is
r_k = (f_k - z_k) / (H dt), its forecast f_k minus hold's z_k over the horizon, per channel. Had a gap
begun at k, the default coast (coast_tau_s 0.2 s, coast_shape 1.5: v(u) = v exp(-(u / tau)^1.5),
docs/MODELS.md §15) would have moved the forecast by d_k(u) = r_k C(u), C(u) the integral of that
decay over u. For each lag of m frames (u = m dt) the least-squares factor

    w*(m) = sum d_k y_k / sum d_k^2,   y_k = z_(k+m) - z_k   (both frames measured; per channel and pooled)

says how the track's own motion would have scaled that coast: below 1, coast less (the motion
reverses or stops within u more often than it goes on); above 1, coast further. The noise of z adds
the same to every candidate and does not move w*. It is an in-sample figure: it uses the whole
track, future included, so no causal rule can do better on average than coasting w* times as far.
"""
import argparse
import csv
import math
import sys


def coast_time(u, tau=0.2, shape=1.5, steps=400):
    """C(u): the integral over [0, u] of exp(-(s / tau)^shape) ds (midpoint rule)."""
    h = u / steps
    return sum(math.exp(-(((i + 0.5) * h) / tau) ** shape) * h for i in range(steps))


def number(cell):
    try:
        x = float(cell)
    except ValueError:
        return None
    return None if math.isnan(x) else x


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("track")
    ap.add_argument("predictions")
    ap.add_argument("--predictor", required=True)
    ap.add_argument("--lags", default="2,6,12,18,24,32", help="lags in frames (default 2,6,12,18,24,32)")
    ap.add_argument("--coast-tau-s", type=float, default=0.2)
    ap.add_argument("--coast-shape", type=float, default=1.5)
    a = ap.parse_args()
    try:
        lags = [int(x) for x in a.lags.split(",")]
        if any(m < 1 for m in lags):
            raise ValueError
    except ValueError:
        sys.exit(f"coast-regression.py: --lags: expected a comma list of whole frames >= 1, got '{a.lags}'")
    try:
        with open(a.track, newline="") as f:
            track = list(csv.DictReader(f))
        with open(a.predictions, newline="") as f:
            pred = list(csv.DictReader(f))
    except OSError as e:
        sys.exit(f"coast-regression.py: {e.filename}: {e.strerror}")
    for name, rows, cols in ((a.track, track, ("t", "u", "v")),
                             (a.predictions, pred, ("t", "t_target", "u", "v", f"{a.predictor}.u_pred"))):
        if not rows or any(c not in rows[0] for c in cols):
            sys.exit(f"coast-regression.py: {name}: expected the columns {', '.join(cols)}")
    if len(pred) != len(track):
        sys.exit(f"coast-regression.py: {a.predictions}: {len(pred)} rows against {len(track)} in {a.track}")
    t = [float(r["t"]) for r in track]
    dt = (t[-1] - t[0]) / (len(t) - 1)
    horizon = float(pred[0]["t_target"]) - float(pred[0]["t"])
    z = {c: [number(r[c]) for r in track] for c in ("u", "v")}
    rate = {c: [None if number(p[c]) is None else (float(p[f"{a.predictor}.{c}_pred"]) - number(p[c])) / horizon
                for p in pred] for c in ("u", "v")}
    print(f"{a.predictor}: {len(t)} frames, dt {dt:.6g} s, horizon {horizon:.6g} s; coast tau {a.coast_tau_s} s, shape {a.coast_shape}")
    print(f"{'lag':>4} {'u [s]':>7} {'C(u) [s]':>9} {'pairs':>6} {'w* u':>6} {'w* v':>6} {'w* both':>8}")
    for m in lags:
        cu = coast_time(m * dt, a.coast_tau_s, a.coast_shape)
        sums = {}
        for c in ("u", "v"):
            s_dd = s_dy = 0.0
            n = 0
            for k in range(len(t) - m):
                if z[c][k] is None or z[c][k + m] is None or rate[c][k] is None:
                    continue
                d = rate[c][k] * cu
                s_dd += d * d
                s_dy += d * (z[c][k + m] - z[c][k])
                n += 1
            sums[c] = (s_dd, s_dy, n)
        ratio = lambda dd, dy: dy / dd if dd > 0.0 else float("nan")
        both = ratio(sums["u"][0] + sums["v"][0], sums["u"][1] + sums["v"][1])
        print(f"{m:4d} {m * dt:7.3f} {cu:9.4f} {sums['u'][2] + sums['v'][2]:6d} {ratio(*sums['u'][:2]):6.3f} "
              f"{ratio(*sums['v'][:2]):6.3f} {both:8.3f}")


if __name__ == "__main__":
    main()
