#!/usr/bin/env python3
"""predvs — one line per directory of scripts/study-grids.sh: over its grids' study.csv, the
(predictor, track) pairs that do not beat hold (ratio_to_hold >= 1) per grid and in all, the
geometric mean of the ratios to hold per grid, the tracks on which imm is above 1.1 times the
smaller of kf-cv's and kf-ca's RMSE (issue 11 item 4; when those three ran), and the tracks on
which imm does not beat hold. With --only NAME the losses and means are NAME's alone.

    scripts/study-summary.py [--only NAME] DIR [DIR ...]
"""
import csv
import math
import os
import sys

GRIDS = ["g1", "g2", "g3", "g4", "g5", "g6", "g7", "v8", "v9", "v10"]


def summary(d, only=None):
    losses, means, imm_miss, imm_hold = [], [], 0, 0
    for g in GRIDS:
        path = os.path.join(d, g, "study.csv")
        if not os.path.exists(path):
            continue
        tracks, loss, logs = {}, 0, []
        with open(path) as f:
            for r in csv.DictReader(f):
                key = (r["kind"], r["rate_hz"], r["noise_px"], r["seed"], r.get("draw", "0"))
                tracks.setdefault(key, {})[r["predictor"]] = float(r["rmse_truth_px"])
                if r["predictor"] != "hold" and only in (None, r["predictor"]):
                    x = float(r["ratio_to_hold"])
                    logs.append(math.log(x))
                    loss += x >= 1.0
        losses.append((g, loss))
        means.append(math.exp(sum(logs) / len(logs)) if logs else float("nan"))
        for v in tracks.values():
            if {"imm", "kf-cv", "kf-ca"} <= v.keys() and v["imm"] > 1.1 * min(v["kf-cv"], v["kf-ca"]):
                imm_miss += 1
            if "imm" in v and v["imm"] >= v["hold"]:
                imm_hold += 1
    if not losses:
        sys.exit(f"{d}: no grid's study.csv")
    return (f"{d}: losses {'/'.join(str(n) for _, n in losses)} (in all {sum(n for _, n in losses)}; "
            f"grids {' '.join(g for g, _ in losses)}); geometric mean ratio {' '.join(f'{m:.4f}' for m in means)}; "
            f"imm above 1.1 x min(kf-cv, kf-ca) on {imm_miss}, at or above hold on {imm_hold} tracks")


if __name__ == "__main__":
    args, only = sys.argv[1:], None
    if args[:1] == ["--only"]:
        if len(args) < 2:
            sys.exit(__doc__)
        only, args = args[1], args[2:]
    if not args:
        sys.exit(__doc__)
    for d in args:
        print(summary(d, only))
