#!/usr/bin/env python3
"""predvs — a recorded track replayed at other frame rates and noise levels, and a check of
`predvs predict --predictor all` against `hold` on it (docs/PERFORMANCE.md, "A recorded track at
other frame rates").

The generators (`predvs make-track`, scripts/foreign-tracks.py) draw the motions they were written
for. This script takes a track that a camera and a tracker produced instead: the feature points of
an image sequence (`--images`, tracked once by `predvs track --source SOURCE`), or a wide track
file (`--track`, columns t,u0,v0,u1,v1,... as `predvs track` writes tracks_wide.csv). Frame k is
stamped t = k / RATE for each rate (the same images seen at that frame rate: the motion in px per
frame is the recording's, in px/s it scales with the rate), and Gaussian noise of each level is
added to the measured cells (a cell without a measurement stays empty). The recorded positions are
the truth columns, so every predictor's RMSE against them, 2 frames ahead (--delay-frames H), is
compared with hold's.

    scripts/recorded-track.py BIN (--images PATTERN [--source dots] | --track WIDE.csv)
                              [--rates 10,15,20,30,60] [--noise 0,0.5,1,2,3] [--seed S] [--seeds N]
                              [--predictors LIST] [--delay-frames H] [--predict-args '...'] [--jobs J] [--out DIR]
                              [--check]

Writes DIR/results.csv (one row per replay and predictor: kind = the recording's name, rate, noise,
seed, predictor, rmse_truth_px, ratio to hold) and prints the same summary as
scripts/foreign-tracks.py. Noise 0 is run once (seed S); each other level with seeds S..S+N-1.
Exit status 0 even when some predictor loses, unless --check is given: then 1 and one line per
loss; 2 on a bad argument or a failed predvs run.
"""
import argparse
import csv
import importlib.util
import os
import random
import subprocess
import sys
import tempfile

_spec = importlib.util.spec_from_file_location(
    "foreign_tracks", os.path.join(os.path.dirname(os.path.abspath(__file__)), "foreign-tracks.py"))
foreign_tracks = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(foreign_tracks)


def read_wide(path):
    """(header, rows) of a wide track: t then u<i>,v<i> pairs; rows as lists of cell strings."""
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    if not rows:
        raise RuntimeError(f"{path}: the file is empty")
    header = rows[0]
    points = (len(header) - 1) // 2
    if header[0] != "t" or points < 1 or header[1:] != [f"{a}{i}" for i in range(points) for a in "uv"]:
        raise RuntimeError(f"{path}:1: expected the header t,u0,v0,u1,v1,... (a tracks_wide.csv), got {','.join(header)}")
    for n, row in enumerate(rows[1:], start=2):
        if len(row) != len(header):
            raise RuntimeError(f"{path}:{n}: expected {len(header)} cells, got {len(row)}")
    return header, rows[1:]


def track_images(bin_path, pattern, source, work):
    """Tracks the image sequence once with `predvs track` and returns its tracks_wide.csv."""
    out = os.path.join(work, "recording")
    cmd = [bin_path, "track", "--images", pattern, "--source", source, "--predictor", "hold", "--delay-frames", "1",
           "--fps", "30", "--no-plots", "--out", out]
    res = subprocess.run(cmd, capture_output=True, text=True)
    if res.returncode != 0:
        raise RuntimeError(f"{' '.join(cmd)}: {res.stderr.strip()}")
    return os.path.join(out, "tracks_wide.csv")


def write_replay(header, rows, rate, noise, seed, path):
    """The recording stamped t = k / rate, noise added to the measured cells, the recording as truth."""
    rng = random.Random(f"{rate}/{noise}/{seed}")
    points = (len(header) - 1) // 2
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["t"] + header[1:] + [f"{a}{i}_true" for i in range(points) for a in "uv"])
        for k, row in enumerate(rows):
            cells = [f"{float(x) + rng.gauss(0, noise):.6f}" if x.strip() and noise > 0 else x for x in row[1:]]
            w.writerow([f"{k / rate:.9g}"] + cells + row[1:])


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0], formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("bin", help="the predvs binary")
    src = ap.add_mutually_exclusive_group(required=True)
    src.add_argument("--images", help="an image sequence for `predvs track --images` (e.g. a printf pattern)")
    src.add_argument("--track", help="a wide track file t,u0,v0,... (tracks_wide.csv of `predvs track`)")
    ap.add_argument("--source", default="dots", help="the tracker of --images (`predvs track --source`, default dots)")
    ap.add_argument("--name", default="", help="the recording's name in the results (default: from --images / --track)")
    ap.add_argument("--out", default="out/recorded-track", help="output directory of results.csv (default out/recorded-track)")
    ap.add_argument("--rates", default="10,15,20,30,60", help="comma list of frame rates the recording is stamped at, Hz")
    ap.add_argument("--noise", default="0,0.5,1,2,3", help="comma list of noise std added per coordinate, px")
    ap.add_argument("--seed", type=int, default=1, help="first seed S of the added noise (default 1)")
    ap.add_argument("--seeds", type=int, default=3, help="replays per noise level > 0, seeds S..S+N-1 (default 3)")
    foreign_tracks.add_predict_arguments(ap, "replay")
    args = ap.parse_args()
    rates, noises = foreign_tracks.rates_and_noise(ap, args)
    if not os.access(args.bin, os.X_OK):
        ap.error(f"{args.bin}: not an executable")
    name = args.name or os.path.basename(os.path.dirname(args.images) if args.images else args.track)
    cells = [(r, n, s) for r in rates for n in noises
             for s in (range(args.seed, args.seed + args.seeds) if n > 0 else [args.seed])]
    try:
        with tempfile.TemporaryDirectory(prefix="recorded-track-") as work:
            wide = track_images(args.bin, args.images, args.source, work) if args.images else args.track
            header, rows = read_wide(wide)

            def replay(cell, cell_work):
                rate, noise, seed = cell
                base = os.path.join(cell_work, f"{rate:g}hz-{noise:g}px-{seed}")
                write_replay(header, rows, rate, noise, seed, base + ".csv")
                return name, rate, noise, seed, foreign_tracks.predict_rmse(args, base + ".csv", base)

            results = foreign_tracks.run_cells("recorded-track", replay, cells, args.jobs, "replays")
    except RuntimeError as e:
        print(f"recorded-track: error: {e}", file=sys.stderr)
        return 2
    except OSError as e:
        print(f"recorded-track: error: {e.filename}: {e.strerror}", file=sys.stderr)
        return 2
    print(f"{name}: {len(rows)} frames, {(len(header) - 1) // 2} points; {len(cells)} replays")
    return foreign_tracks.report(results, args.out, [name], args.check, args.delay_frames)


if __name__ == "__main__":
    sys.exit(main())
