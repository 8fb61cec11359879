#!/usr/bin/env python3
"""Test of scripts/foreign-tracks.py --draw (docs/PERFORMANCE.md "Losses are draws, not motions").

  foreign_tracks_draw_test.py PREDVS WORKDIR

GIVEN one track of the second generator (dash 10 Hz 1 px #2, empty cells for lost frames), WHEN it
is written without --draw, with --draw 0 and with --draw 1 (--keep-tracks), THEN --draw 0 is the
same bytes as no --draw, draw 1 has the same truth on every row and other measurements (noise and
lost frames), and its file name carries the draw; --draw -1 is refused in one line naming the option,
with exit status 2 and nothing written.
"""
import csv
import os
import sys

from script_test import arguments, checked, finish, run, script

SCRIPT = script("foreign-tracks.py")
CELL = ["--kinds", "dash", "--rates", "10", "--noise", "1", "--seed", "2", "--seeds", "1"]


def track(predvs, out, draw_args):
    checked([sys.executable, SCRIPT, predvs, *CELL, *draw_args, "--predictors", "hold,kf-cv", "--jobs", "1",
             "--keep-tracks", "--out", out])
    names = os.listdir(os.path.join(out, "tracks"))
    if len(names) != 1:
        sys.exit(f"{out}/tracks: expected one track, got {names}")
    return os.path.join(out, "tracks", names[0])


def main():
    predvs, work = arguments()
    failures = []
    plain = track(predvs, os.path.join(work, "plain"), [])
    zero = track(predvs, os.path.join(work, "zero"), ["--draw", "0"])
    one = track(predvs, os.path.join(work, "one"), ["--draw", "1"])
    with open(plain, "rb") as a, open(zero, "rb") as b:
        if a.read() != b.read():
            failures.append("--draw 0 is not the track without --draw")
    if not os.path.basename(one).endswith("-d1.csv"):
        failures.append(f"draw 1's file is {os.path.basename(one)}, expected a name ending in -d1.csv")
    with open(plain) as f:
        rows0 = list(csv.DictReader(f))
    with open(one) as f:
        rows1 = list(csv.DictReader(f))
    if len(rows0) != len(rows1):
        failures.append(f"{len(rows0)} rows against {len(rows1)} (lost frames are empty cells for an even seed)")
    else:
        # the truth at each frame is the motion's, whatever the timestamp jitter: compare the
        # truth columns as written, which sample the same 1 kHz motion at jittered times, loosely
        far = sum(1 for a, b in zip(rows0, rows1) if abs(float(a["u_true"]) - float(b["u_true"])) > 5.0)
        same_meas = sum(1 for a, b in zip(rows0, rows1) if a["u"] == b["u"])
        if far > len(rows0) // 20:
            failures.append(f"the truth differs by more than 5 px on {far} of {len(rows0)} rows")
        if same_meas > len(rows0) // 10:
            failures.append(f"{same_meas} of {len(rows0)} measured cells are the same in draw 1")
    bad = os.path.join(work, "bad")
    r = run([sys.executable, SCRIPT, predvs, *CELL, "--draw", "-1", "--out", bad])
    lines = r.stderr.strip().splitlines()
    if r.returncode != 2 or "--draw" not in (lines[-1] if lines else "") or os.path.exists(bad):
        failures.append(f"--draw -1: exit {r.returncode}, stderr {r.stderr.strip()!r}, output written: {os.path.exists(bad)}")
    finish(failures, "foreign-tracks --draw: draw 0 is the track as before; draw 1 keeps the motion, redraws the rest")


if __name__ == "__main__":
    main()
