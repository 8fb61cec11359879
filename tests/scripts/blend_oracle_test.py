#!/usr/bin/env python3
"""Test of scripts/blend-oracle.py (docs/PERFORMANCE.md "Two blend weights").

  blend_oracle_test.py PREDVS WORKDIR

GIVEN a make-track track, WHEN blend-oracle fits the best constant blend weights of kf-cv on it,
THEN both fitted blends are at most hold's error (w = 0 is hold, and the fit is free to choose it),
the two weights at most the one weight (w_s = w_x = w is one of their choices), and the causal ratio
is a positive number; and a track without truth, or a missing one, is refused with a one-line error
(naming the column, or the file) and a non-zero exit.
"""
import os
import re
import sys

from script_test import arguments, checked, finish, refused_in_one_line, run, script

SCRIPT = script("blend-oracle.py")


def main():
    predvs, work = arguments()
    track = os.path.join(work, "t.csv")
    checked([predvs, "make-track", "--kind", "zigzag", "--rate-hz", "10", "--noise-px", "3", "--duration-s", "15",
             "--seed", "2", "--out", track])
    r = checked([sys.executable, SCRIPT, predvs, track, "--work", os.path.join(work, "o")])
    ratios = [float(m) for m in re.findall(r"^\s+.*?\s(\d+\.\d+)(?:\s|$)", r.stdout, re.M)]
    failures = []
    if len(ratios) != 3:
        failures.append(f"expected three ratios, got {ratios} from {r.stdout!r}")
    else:
        causal, two, one = ratios
        if not causal > 0.0:
            failures.append(f"causal ratio {causal}")
        if not one <= 1.0 + 1e-9:
            failures.append(f"the fitted one weight ({one}) is worse than hold (w = 0)")
        if not two <= one + 1e-9:
            failures.append(f"the fitted two weights ({two}) are worse than the one weight ({one})")
    bare = os.path.join(work, "bare.csv")
    with open(bare, "w") as f:
        f.write("t,u,v\n0,1,2\n0.1,1,2\n")
    r = run([sys.executable, SCRIPT, predvs, bare])
    if not refused_in_one_line(r, "u_true"):
        failures.append(f"a track without truth was not refused in one line: exit {r.returncode}, {r.stderr!r}")
    r = run([sys.executable, SCRIPT, predvs, os.path.join(work, "missing.csv")])
    if not refused_in_one_line(r, "missing.csv"):
        failures.append(f"a missing track was not refused in one line: exit {r.returncode}, {r.stderr!r}")
    finish(failures)


if __name__ == "__main__":
    main()
