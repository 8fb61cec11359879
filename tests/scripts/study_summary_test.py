#!/usr/bin/env python3
"""Test of scripts/study-summary.py (docs/PERFORMANCE.md "The horizons asked for").

  study_summary_test.py PREDVS WORKDIR

GIVEN a small `predvs track-study` grid written where scripts/study-grids.sh puts its first grid
(DIR/g1/study.csv), 5 frames ahead with the blend on two horizons (some losses to hold), WHEN
study-summary sums it up, THEN its loss count is the one track-study prints (tracks less wins, over
the predictors), with --only NAME NAME's alone, and a directory without any grid is refused in one
line with a non-zero exit.
"""
import os
import re
import sys

from script_test import arguments, checked, finish, refused_in_one_line, run, script

SCRIPT = script("study-summary.py")


def main():
    predvs, work = arguments()
    two = []
    for n in ("kf-cv", "kf-ca", "imm"):
        two += ["--param", f"{n}.hold_blend_frames=2"]
    r = checked([predvs, "track-study", "--kinds", "hand,bursts", "--rates", "10", "--noise", "0.5,3", "--seeds", "2",
                 "--seed", "2", "--delay-frames", "5", "--predictors", "hold,kf-cv,kf-ca,imm", "--jobs", "2",
                 "--out", os.path.join(work, "g1")] + two)
    # the table under "beats hold", up to the "ratio =" line: "kf-cv   7/8   0.87 ..." (wins / tracks)
    table = r.stdout[r.stdout.index("beats hold"):r.stdout.index("ratio =")]
    rows = {m.group(1): int(m.group(3)) - int(m.group(2)) for m in re.finditer(r"^(\S+)\s+(\d+)/(\d+)\s", table, re.M)}
    printed = sum(rows.values())
    s = checked([sys.executable, SCRIPT, work])
    m = re.search(r"losses (\d+) \(in all (\d+); grids g1\)", s.stdout)
    failures = []
    if not m:
        failures.append(f"no loss count in {s.stdout!r}")
    elif int(m.group(2)) != printed:
        failures.append(f"{m.group(2)} losses against track-study's {printed}")
    elif printed == 0:
        failures.append("no loss on the grid: the check would not tell a wrong count")
    for name in ("kf-cv", "imm"):
        o = checked([sys.executable, SCRIPT, "--only", name, work])
        m = re.search(r"losses (\d+) \(in all (\d+); grids g1\)", o.stdout)
        if not m or int(m.group(2)) != rows.get(name, -1):
            failures.append(f"--only {name}: {o.stdout!r} against track-study's {rows.get(name)}")
    if sum(1 for n in ("kf-cv", "imm") if rows.get(n)) == 0:
        failures.append("neither kf-cv nor imm loses on the grid: --only would not tell a wrong count")
    empty = os.path.join(work, "empty")
    os.makedirs(empty, exist_ok=True)
    if not refused_in_one_line(run([sys.executable, SCRIPT, empty]), "study.csv"):
        failures.append("a directory without a grid was not refused in one line")
    finish(failures, f"study-summary: {printed} losses, as track-study prints")


if __name__ == "__main__":
    main()
