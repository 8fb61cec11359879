#!/usr/bin/env python3
"""predvs — split the forecast errors of `predvs predict` into the rows made on a measured frame and
the rows made in a gap (docs/PERFORMANCE.md, "imm's forecast weights in a gap").

  scripts/gap-split.py TRACK.csv PREDICTIONS.csv

TRACK.csv is a track with truth, as `predvs make-track` writes it (t,u,v,u_true,v_true; an empty u
is a dropped frame); PREDICTIONS.csv is what `predvs predict --input TRACK.csv` wrote for it. The
prediction of row i is compared with the truth at its target time t_i + horizon, linearly
interpolated between the rows around it (exact when the target is a row time); rows whose target
is past the last measured frame are left out. The whole is `predict`'s RMSE vs truth up to a row
or two at the ends. For each predictor, prints the RMSE over all scored
rows and its two parts, sqrt(sum of the squared errors of the part / all scored rows), so that the
squares of the parts add up to the square of the whole.
"""
import bisect
import csv
import math
import sys


def main():
    if len(sys.argv) != 3:
        sys.exit("usage: gap-split.py TRACK.csv PREDICTIONS.csv")
    with open(sys.argv[1], newline="") as f:
        track = list(csv.DictReader(f))
    with open(sys.argv[2], newline="") as f:
        pred = list(csv.DictReader(f))
    if len(track) != len(pred):
        sys.exit(f"{sys.argv[2]}: {len(pred)} rows, {sys.argv[1]} has {len(track)}")
    for key in ("u", "u_true", "v_true"):
        if key not in track[0]:
            sys.exit(f"{sys.argv[1]}: no column '{key}' (a track with truth, as make-track writes)")
    t = [float(r["t"]) for r in track]
    ut = [float(r["u_true"]) for r in track]
    vt = [float(r["v_true"]) for r in track]
    names = [k[: -len(".u_pred")] for k in pred[0] if k.endswith(".u_pred")]
    last_measured = max((t[i] for i, r in enumerate(track) if r["u"] != ""), default=-math.inf)

    def truth_at(x):
        k = bisect.bisect_left(t, x)
        if k >= len(t):
            return None
        if t[k] == x or k == 0:
            return ut[k], vt[k]
        w = (x - t[k - 1]) / (t[k] - t[k - 1])
        return (1 - w) * ut[k - 1] + w * ut[k], (1 - w) * vt[k - 1] + w * vt[k]

    sums = {n: [0.0, 0.0] for n in names}
    rows = [0, 0]
    for i, r in enumerate(pred):
        target = float(r["t_target"])
        ref = truth_at(target) if target <= last_measured else None
        if ref is None:
            continue
        part = 1 if track[i]["u"] == "" else 0
        rows[part] += 1
        for n in names:
            du = float(r[n + ".u_pred"]) - ref[0]
            dv = float(r[n + ".v_pred"]) - ref[1]
            sums[n][part] += du * du + dv * dv
    total = rows[0] + rows[1]
    if total == 0:
        sys.exit(f"{sys.argv[2]}: no scored row")
    print(f"rows scored: {total}, made on a measured frame {rows[0]}, made in a gap {rows[1]}")
    print(f"{'predictor':<18}{'rmse':>8}{'measured':>10}{'gap':>8}")
    for n in names:
        whole = math.sqrt((sums[n][0] + sums[n][1]) / total)
        print(f"{n:<18}{whole:8.3f}{math.sqrt(sums[n][0] / total):10.3f}{math.sqrt(sums[n][1] / total):8.3f}")


if __name__ == "__main__":
    main()
