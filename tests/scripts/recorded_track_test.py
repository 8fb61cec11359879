#!/usr/bin/env python3
"""Test of scripts/recorded-track.py (docs/PERFORMANCE.md "A recorded track at other frame rates").

  recorded_track_test.py PREDVS WORKDIR

GIVEN a wide track of two points that sway slowly and step once by 15 px in one frame, WHEN
recorded-track replays it at 10 Hz without added noise, THEN its results.csv holds one row per
predictor, hold's ratio is not listed, kf-ca beats hold with its defaults and loses to it without
its extrapolation cap (the same track, `--param kf-ca.extrapolation_cap=0`), and --check exits 1
with one line per loss there; a file that is not a wide track is refused with a one-line error
that names it and a non-zero exit, and nothing is written; so is a predictor list without hold.
"""
import csv
import math
import os
import sys

from script_test import arguments, finish, run, script

SCRIPT = script("recorded-track.py")


def write_track(path):
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["t", "u0", "v0", "u1", "v1"])
        for k in range(300):
            t = k / 30.0  # any stamps: the script restamps the rows
            step = 15.0 if k >= 150 else 0.0
            u = 320 + 20 * math.sin(2 * math.pi * 0.05 * k / 10) + 0.02 * ((k * 7919) % 13 - 6)
            v = 240 + 15 * math.cos(2 * math.pi * 0.04 * k / 10) + 0.02 * ((k * 104729) % 11 - 5)
            w.writerow([f"{t:.6f}", f"{u + step:.4f}", f"{v:.4f}", f"{u + 60 + step:.4f}", f"{v - 40:.4f}"])


def replay(predvs, track, out, extra=()):
    return run([sys.executable, SCRIPT, predvs, "--track", track, "--rates", "10", "--noise", "0",
                "--predictors", "hold,kf-ca", "--jobs", "1", "--out", out] + list(extra))


def kf_ca_ratio(out):
    with open(os.path.join(out, "results.csv")) as f:
        rows = list(csv.DictReader(f))
    if [r["predictor"] for r in rows] != ["kf-ca"]:
        sys.exit(f"{out}/results.csv: expected one row, kf-ca's, got {[r['predictor'] for r in rows]}")
    return float(rows[0]["ratio_to_hold"])


def main():
    predvs, work = arguments()
    track = os.path.join(work, "stepped.csv")
    write_track(track)
    failures = []
    r = replay(predvs, track, os.path.join(work, "capped"))
    if r.returncode != 0:
        sys.exit(f"recorded-track failed: {r.stderr.strip()}")
    capped = kf_ca_ratio(os.path.join(work, "capped"))
    r = replay(predvs, track, os.path.join(work, "free"), ["--predict-args=--param kf-ca.extrapolation_cap=0", "--check"])
    free = kf_ca_ratio(os.path.join(work, "free"))
    if not capped < 1.0 < free:
        failures.append(f"kf-ca / hold: {capped:.3f} with the cap, {free:.3f} without; expected below and above 1")
    if r.returncode != 1 or "kf-ca does not beat hold" not in r.stderr:
        failures.append(f"--check on a loss: exit {r.returncode}, stderr {r.stderr!r}")
    bad = os.path.join(work, "bad.csv")
    with open(bad, "w") as f:
        f.write("t,x,y\n0,1,2\n")
    r = replay(predvs, bad, os.path.join(work, "bad"))
    lines = r.stderr.strip().split("\n")
    if r.returncode != 2 or len(lines) != 1 or "bad.csv:1" not in lines[0] or os.path.exists(os.path.join(work, "bad")):
        failures.append(f"a file that is not a wide track: exit {r.returncode}, stderr {r.stderr!r}")
    r = run([sys.executable, SCRIPT, predvs, "--track", track, "--predictors", "kf-cv", "--out", os.path.join(work, "nohold")])
    if r.returncode != 2 or "has no hold" not in r.stderr or os.path.exists(os.path.join(work, "nohold")):
        failures.append(f"a predictor list without hold: exit {r.returncode}, stderr {r.stderr!r}")
    finish(failures, f"recorded-track: kf-ca / hold {capped:.3f} with the cap, {free:.3f} without")


if __name__ == "__main__":
    main()
