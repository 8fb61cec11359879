#!/usr/bin/env python3
"""Test of scripts/gap-split.py (docs/PERFORMANCE.md "imm's forecast weights in a gap").

  gap_split_test.py PREDVS WORKDIR

GIVEN a make-track track with occlusions and `predvs predict` on it, WHEN gap-split splits the
errors, THEN the parts' squares add up to the whole's square, the whole is predict's RMSE vs truth
to within 1 %, hold's error is in both parts, and a predictions file of another track is refused
with a one-line error and a non-zero exit.
"""
import json
import math
import os
import sys

from script_test import arguments, checked, finish, refused_in_one_line, run, script

SCRIPT = script("gap-split.py")


def main():
    predvs, work = arguments()
    track = os.path.join(work, "t.csv")
    out = os.path.join(work, "p")
    checked([predvs, "make-track", "--kind", "bursts", "--rate-hz", "60", "--noise-px", "1", "--duration-s", "10",
             "--drop", "0.08", "--seed", "3", "--out", track])
    checked([predvs, "predict", "--input", track, "--predictor", "hold,kf-cv", "--delay-frames", "2", "--no-plots",
             "--out", out])
    r = checked([sys.executable, SCRIPT, track, os.path.join(out, "predictions.csv")])
    lines = r.stdout.strip().split("\n")
    rows = {f[0]: tuple(float(x) for x in f[1:]) for f in (l.split() for l in lines[2:])}
    with open(os.path.join(out, "summary.json")) as f:
        truth = {p["name"]: p["vs_truth"]["rmse_px"] for p in json.load(f)["predictors"]}
    failures = []
    for name in ("hold", "kf-cv"):
        whole, measured, gap = rows[name]
        if abs(whole * whole - (measured * measured + gap * gap)) > 2e-3 * whole * whole + 1e-6:
            failures.append(f"{name}: parts {measured}, {gap} do not add up to {whole}")
        if abs(whole / truth[name] - 1.0) > 0.01:
            failures.append(f"{name}: whole {whole} against predict's {truth[name]}")
        if not (measured > 0.0 and gap > 0.0):
            failures.append(f"{name}: an empty part ({measured}, {gap})")
    other = os.path.join(work, "short.csv")
    run([predvs, "make-track", "--kind", "bursts", "--rate-hz", "60", "--duration-s", "5", "--out", other])
    r = run([sys.executable, SCRIPT, other, os.path.join(out, "predictions.csv")])
    if not refused_in_one_line(r, "rows"):
        failures.append(f"a mismatched track was not refused in one line: exit {r.returncode}, {r.stderr!r}")
    finish(failures, "gap-split: " + "; ".join(f"{n} {rows[n][0]:.3f} = ({rows[n][1]:.3f}, {rows[n][2]:.3f})" for n in rows))


if __name__ == "__main__":
    main()
