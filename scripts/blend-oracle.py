#!/usr/bin/env python3
"""predvs — the best constant blend weights of one predictor on one track, in hindsight
(docs/PERFORMANCE.md, "Two blend weights").

  scripts/blend-oracle.py BIN TRACK.csv [--predictor NAME] [--delay-frames H] [--work DIR]

TRACK.csv is a track with truth (t,u,v,u_true,v_true; an empty u is a dropped frame), as `predvs
make-track` or scripts/foreign-tracks.py writes it (`--keep-tracks`). The script runs `BIN predict`
twice on it: hold, NAME without the blend (`hold_blend_tau_s=0`) and NAME with its defaults H frames
ahead; and NAME without the blend 0 frames ahead (the filtered position p0 the forecast starts
from; for a per-channel filter the forecast weighting scales the velocity only, so this is its start). On every frame with a measurement whose target time has a truth it forms, per
coordinate, the steps of the blend (docs/MODELS.md §15, "Two weights"):
  d_s = p0 - z_hold,  d_x = x_m - p0,  y = truth(t + horizon) - z_hold,
and fits y ~ w_s d_s + w_x d_x, and y ~ w (d_s + d_x), by least squares over the whole track,
without bounds. It prints the RMSE vs truth, as a ratio to hold's, of NAME with its defaults (the
blend learnt causally), and of the two fitted blends with their weights: what the best constant
weights, chosen knowing the whole track, would have given.
"""
import argparse
import bisect
import csv
import math
import os
import subprocess
import sys
import tempfile


def predict(bin_path, track, out, predictors, delay):
    cmd = [bin_path, "predict", "--input", track, "--predictor", predictors, "--delay-frames", str(delay),
           "--no-plots", "--jobs", "1", "--out", out]
    res = subprocess.run(cmd, capture_output=True, text=True)
    if res.returncode != 0:
        sys.exit(f"{' '.join(cmd)}: {res.stderr.strip()}")
    with open(os.path.join(out, "predictions.csv"), newline="") as f:
        return list(csv.DictReader(f))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("bin", help="the predvs binary")
    ap.add_argument("track", help="track CSV with truth (t,u,v,u_true,v_true)")
    ap.add_argument("--predictor", default="kf-cv", help="a per-channel predictor (default kf-cv)")
    ap.add_argument("--delay-frames", type=int, default=2, help="horizon in frames (default 2)")
    ap.add_argument("--work", help="directory for predict's outputs (default: a temporary one)")
    args = ap.parse_args()
    try:
        with open(args.track, newline="") as f:
            rows = list(csv.DictReader(f))
    except OSError as e:
        sys.exit(f"{args.track}: {e.strerror}")
    for key in ("t", "u", "v", "u_true", "v_true"):
        if not rows or key not in rows[0]:
            sys.exit(f"{args.track}: no column '{key}' (a track with truth, as make-track writes)")
    work = args.work or tempfile.mkdtemp(prefix="blend-oracle-")
    name = args.predictor
    ahead = predict(args.bin, args.track, os.path.join(work, "ahead"),
                    f"hold,raw={name}:hold_blend_tau_s=0,blended={name}", args.delay_frames)
    start = predict(args.bin, args.track, os.path.join(work, "start"), f"raw={name}:hold_blend_tau_s=0", 0)
    t = [float(r["t"]) for r in rows]
    truth = {"u": [float(r["u_true"]) for r in rows], "v": [float(r["v_true"]) for r in rows]}

    def truth_at(ax, x):
        k = bisect.bisect_left(t, x - 1e-9)
        if k >= len(t):
            return None
        if abs(t[k] - x) <= 1e-9 or k == 0:
            return truth[ax][k]
        w = (x - t[k - 1]) / (t[k] - t[k - 1])
        return (1 - w) * truth[ax][k - 1] + w * truth[ax][k]

    samples = []  # (d_s, d_x, y, squared error of the causal blend)
    for i, r in enumerate(rows):
        if r["u"] == "" or r["v"] == "":
            continue
        for ax in ("u", "v"):
            ref = truth_at(ax, float(ahead[i]["t_target"]))
            if ref is None:
                continue
            z_hold = float(ahead[i][f"hold.{ax}_pred"])
            x_m = float(ahead[i][f"raw.{ax}_pred"])
            p0 = float(start[i][f"raw.{ax}_pred"])
            causal = float(ahead[i][f"blended.{ax}_pred"])
            samples.append((p0 - z_hold, x_m - p0, ref - z_hold, (causal - ref) ** 2))
    if len(samples) < 3:
        sys.exit(f"{args.track}: fewer than 3 scored samples")
    n = len(samples)
    hold_ms = sum(y * y for _, _, y, _ in samples) / n
    a11 = sum(s * s for s, _, _, _ in samples)
    a12 = sum(s * x for s, x, _, _ in samples)
    a22 = sum(x * x for _, x, _, _ in samples)
    b1 = sum(s * y for s, _, y, _ in samples)
    b2 = sum(x * y for _, x, y, _ in samples)
    det = a11 * a22 - a12 * a12
    if not det > 0:
        sys.exit(f"{args.track}: the two steps are collinear")
    w_s, w_x = (a22 * b1 - a12 * b2) / det, (a11 * b2 - a12 * b1) / det
    split_ms = sum((w_s * s + w_x * x - y) ** 2 for s, x, y, _ in samples) / n
    dd = sum((s + x) ** 2 for s, x, _, _ in samples)
    w = sum((s + x) * y for s, x, y, _ in samples) / dd
    one_ms = sum((w * (s + x) - y) ** 2 for s, x, y, _ in samples) / n
    causal_ms = sum(e for _, _, _, e in samples) / n
    print(f"{args.track}: {name}, {args.delay_frames} frames ahead, {n} samples; RMSE vs truth / hold's")
    print(f"  {name} (its defaults, learnt on the way)  {math.sqrt(causal_ms / hold_ms):.3f}")
    print(f"  best constant two weights               {math.sqrt(split_ms / hold_ms):.3f}  (w_s {w_s:.2f}, w_x {w_x:.2f})")
    print(f"  best constant one weight                {math.sqrt(one_ms / hold_ms):.3f}  (w {w:.2f})")


if __name__ == "__main__":
    main()
