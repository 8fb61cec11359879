#!/usr/bin/env python3
"""predvs — a second track generator, independent of `predvs make-track`, and a check of
`predvs predict --predictor all` against `hold` on its tracks (docs/PERFORMANCE.md, "Tracks from
a second generator").

The defaults of issue 11 were chosen on make-track's tracks. This script draws other motions with
other code (orbits with a varying rate, stop-and-go with hard decelerations, minimum-jerk dashes,
saw-tooth zigzags, an Ornstein-Uhlenbeck hand with tremor, sums of sines), samples them at a
frame rate with optional timestamp jitter, adds Gaussian pixel noise, and loses frames either as
missing rows or as empty cells (single frames at random plus occlusions of 3-10 frames). Each
track is written as a wide CSV (t,u,v,u_true,v_true) and run through `predvs predict --predictor
all --delay-frames 2 --no-plots` (--delay-frames H for another horizon); the RMSE against the
truth of every predictor is compared with hold's.

    scripts/foreign-tracks.py BIN [--out DIR] [--seed S] [--seeds N] [--rates 10,15,...]
                              [--noise 0.5,1,...] [--duration-s T] [--drop P] [--jitter F]
                              [--kinds a,b,...] [--draw D] [--predictors LIST] [--delay-frames H]
                              [--predict-args '...'] [--jobs J] [--check]

Writes DIR/results.csv (one row per track and predictor: kind, rate, noise, seed, predictor,
rmse_truth_px, ratio to hold) and prints, per predictor, the tracks on which it beats hold, the
geometric mean of the ratio and the worst track; and, as `predvs track-study` does, when kf-cv,
kf-ca or cs-akf run, per other predictor the tracks on which it is within 10 % of the best of them
(in all and per kind; issue 11 items 3 and 4). Exit status 0 even when some predictor loses (a
study), unless --check is given: then 1 and one line per loss (the test `foreign_tracks` runs a
small grid so); 2 on a bad argument or a failed predvs run.
"""
import argparse
import concurrent.futures
import csv
import json
import math
import os
import random
import shutil
import subprocess
import sys
import tempfile

SUBSTEP_HZ = 1000.0  # truth integrated at 1 kHz, then sampled at the frame times


def orbit(rng, duration):
    """An ellipse whose angular rate changes smoothly and now and then reverses (turns)."""
    cx, cy = 320 + rng.uniform(-60, 60), 240 + rng.uniform(-40, 40)
    a, b = rng.uniform(40, 150), rng.uniform(40, 150)
    w0 = rng.uniform(0.6, 2.2) * rng.choice([-1, 1])
    f1, f2 = rng.uniform(0.05, 0.3), rng.uniform(0.05, 0.3)
    p1, p2 = rng.uniform(0, 6.3), rng.uniform(0, 6.3)
    th, out, dt = 0.0, [], 1.0 / SUBSTEP_HZ
    for i in range(int(duration * SUBSTEP_HZ) + 1):
        t = i * dt
        w = w0 * (0.6 * math.cos(2 * math.pi * f1 * t + p1) + 0.6 + 0.3 * math.sin(2 * math.pi * f2 * t + p2))
        th += w * dt
        out.append((cx + a * math.cos(th), cy + b * math.sin(th)))
    return out


def _integrate(vel_at, duration, start):
    x, y = start
    out, dt = [], 1.0 / SUBSTEP_HZ
    for i in range(int(duration * SUBSTEP_HZ) + 1):
        vx, vy = vel_at(i * dt)
        out.append((x, y))
        x += vx * dt
        y += vy * dt
    return out


def _segments(rng, duration, make):
    """Piecewise velocity: make(rng) -> (length_s, fn(u, length) -> (vx, vy)) until duration."""
    segs, t = [], 0.0
    while t < duration + 1.0:
        length, fn = make(rng)
        segs.append((t, length, fn))
        t += length
    idx = [0]

    def vel(t):
        while idx[0] + 1 < len(segs) and segs[idx[0] + 1][0] <= t:
            idx[0] += 1
        t0, length, fn = segs[idx[0]]
        return fn(t - t0, length)
    return vel


def _rest_and_move(rng, duration, rest_s, move):
    """Rest for uniform(rest_s) seconds, then one move(r) -> (length_s, fn(u, length) -> (vx, vy)),
    and again until duration."""
    state = {"moving": False}

    def make(r):
        state["moving"] = not state["moving"]
        if not state["moving"]:
            return r.uniform(*rest_s), lambda u, L: (0.0, 0.0)
        return move(r)
    return _integrate(_segments(rng, duration, make), duration, (320.0, 240.0))


def stopgo(rng, duration):
    """Cruise at 60-250 px/s, brake to rest in 0.05-0.15 s, stand 0.3-1.5 s, start hard again."""
    def move(r):
        speed, ang = r.uniform(60, 250), r.uniform(0, 2 * math.pi)
        ramp_up, ramp_down = r.uniform(0.05, 0.15), r.uniform(0.05, 0.15)
        vx, vy = speed * math.cos(ang), speed * math.sin(ang)

        def fn(u, L):
            s = min(1.0, u / ramp_up, max(0.0, (L - u) / ramp_down))
            return vx * s, vy * s
        return r.uniform(0.5, 2.0), fn
    return _rest_and_move(rng, duration, (0.3, 1.5), move)


def dash(rng, duration):
    """Rest, then a minimum-jerk move of 30-150 px over 0.2-0.6 s, again and again."""
    def move(r):
        dist, ang = r.uniform(30, 150), r.uniform(0, 2 * math.pi)

        def fn(u, L):
            s = u / L
            speed = dist / L * 30 * s * s * (1 - s) * (1 - s)
            return speed * math.cos(ang), speed * math.sin(ang)
        return r.uniform(0.2, 0.6), fn
    return _rest_and_move(rng, duration, (0.2, 1.2), move)


def saw(rng, duration):
    """Constant speed 50-200 px/s along a drifting axis, reversing every 0.3-1.2 s."""
    speed = rng.uniform(50, 200)
    ang = rng.uniform(0, 2 * math.pi)
    sign = [1.0]

    def make(r):
        sign[0] = -sign[0]
        s, a = sign[0] * speed, ang + r.uniform(-0.4, 0.4)
        return r.uniform(0.3, 1.2), lambda u, L: (s * math.cos(a), s * math.sin(a))
    return _integrate(_segments(rng, duration, make), duration, (320.0, 240.0))


def shake(rng, duration):
    """A hand: Ornstein-Uhlenbeck velocity (tau 0.2-0.6 s, 20-80 px/s) plus 8-12 Hz tremor."""
    tau, sigma = rng.uniform(0.2, 0.6), rng.uniform(20, 80)
    fq, amp = rng.uniform(8, 12), rng.uniform(0.3, 2.0)
    dt = 1.0 / SUBSTEP_HZ
    x, y, vx, vy, out = 320.0, 240.0, 0.0, 0.0, []
    k = math.sqrt(2 * dt / tau) * sigma
    for i in range(int(duration * SUBSTEP_HZ) + 1):
        t = i * dt
        out.append((x + amp * math.sin(2 * math.pi * fq * t), y + amp * math.cos(2 * math.pi * fq * 1.13 * t)))
        vx += -vx / tau * dt + k * rng.gauss(0, 1)
        vy += -vy / tau * dt + k * rng.gauss(0, 1)
        x += vx * dt
        y += vy * dt
    return out


def weave(rng, duration):
    """A sum of three sines per axis, 0.1-1.5 Hz, 10-80 px each."""
    comps = [[(rng.uniform(10, 80), rng.uniform(0.1, 1.5), rng.uniform(0, 6.3)) for _ in range(3)] for _ in range(2)]
    out, dt = [], 1.0 / SUBSTEP_HZ
    for i in range(int(duration * SUBSTEP_HZ) + 1):
        t = i * dt
        out.append(tuple(c0 + sum(a * math.sin(2 * math.pi * f * t + p) for a, f, p in comps[k])
                         for k, c0 in enumerate((320.0, 240.0))))
    return out


KINDS = {"orbit": orbit, "stopgo": stopgo, "dash": dash, "saw": saw, "shake": shake, "weave": weave}


def make_track(kind, rate, noise, seed, duration, drop, jitter, path, draw=0):
    rng = random.Random(f"{kind}/{rate}/{noise}/{seed}")
    truth = KINDS[kind](rng, duration)
    if draw:  # another draw of the jitter, drops and noise over the same motion (--draw)
        rng = random.Random(f"{kind}/{rate}/{noise}/{seed}/draw{draw}")
    n = int(duration * rate)
    style = "rows" if seed % 2 else "cells"
    lost, occluded = False, 0
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["t", "u", "v", "u_true", "v_true"])
        for k in range(n):
            t = (k + (rng.uniform(-jitter, jitter) if k else 0.0)) / rate
            i = min(len(truth) - 1, int(round(t * SUBSTEP_HZ)))
            ut, vt = truth[i]
            if occluded > 0:
                occluded -= 1
                lost = True
            elif k > 20 and rng.random() < drop / 10:
                occluded = rng.randint(2, 9)
                lost = True
            else:
                lost = k > 20 and rng.random() < drop
            if lost and style == "rows":
                continue
            u = "" if lost else f"{ut + rng.gauss(0, noise):.4f}"
            v = "" if lost else f"{vt + rng.gauss(0, noise):.4f}"
            w.writerow([f"{t:.6f}", u, v, f"{ut:.4f}", f"{vt:.4f}"])


def run_one(args, kind, rate, noise, seed, work):
    name = f"{kind}-{rate:g}hz-{noise:g}px-{seed}" + (f"-d{args.draw}" if args.draw else "")
    track = os.path.join(work, name + ".csv")
    make_track(kind, rate, noise, seed, args.duration_s, args.drop, args.jitter, track, args.draw)
    if args.keep_tracks:
        shutil.copy(track, os.path.join(args.out, "tracks", name + ".csv"))
    return kind, rate, noise, seed, predict_rmse(args, track, os.path.join(work, name))


def predict_rmse(args, track, out):
    """Runs `predict --predictor args.predictors --delay-frames args.delay_frames` on track (with
    truth) into out; returns {predictor: RMSE vs truth, px}."""
    cmd = [args.bin, "predict", "--input", track, "--predictor", args.predictors, "--delay-frames", str(args.delay_frames),
           "--no-plots", "--jobs", "1", "--out", out] + args.predict_args.split()
    res = subprocess.run(cmd, capture_output=True, text=True)
    if res.returncode != 0:
        raise RuntimeError(f"{' '.join(cmd)}: {res.stderr.strip()}")
    with open(os.path.join(out, "summary.json")) as f:
        summary = json.load(f)
    return {p["name"]: p["vs_truth"]["rmse_px"] for p in summary["predictors"]}


REFERENCE = ("kf-cv", "kf-ca", "cs-akf")  # the fixed KFs of issue 11's "best fixed KF"


def print_within_best(results, names, kinds):
    """Per predictor other than the fixed KFs: on how many tracks its RMSE is within 10 % of the
    best of the fixed KFs that ran, the geometric mean and worst of that ratio, and the count per kind."""
    ref = [n for n in REFERENCE if n in names]
    others = [n for n in names if n not in ref]
    if not ref or not others:
        return
    print(f"\n{'predictor':16s} {'within 10%':>12s} {'mean ratio':>10s}  worst   (ratio: RMSE vs truth / best of {', '.join(ref)})")
    per_kind = {n: {k: [0, 0] for k in kinds} for n in others}
    for n in others:
        within, log_sum, worst, worst_at = 0, 0.0, 0.0, ""
        for kind, rate, noise, seed, rows in results:
            ratio = rows[n] / min(rows[r] for r in ref)
            ok = ratio <= 1.1
            within += ok
            per_kind[n][kind][0] += ok
            per_kind[n][kind][1] += 1
            log_sum += math.log(ratio)
            if ratio > worst:
                worst, worst_at = ratio, f"{kind} {rate:g} Hz {noise:g} px #{seed}"
        print(f"{n:16s} {within:5d}/{len(results):<6d} {math.exp(log_sum / len(results)):10.3f}  {worst:.3f} ({worst_at})")
    print(f"{'per kind':16s} " + " ".join(f"{k:>8s}" for k in kinds))
    for n in others:
        print(f"{n:16s} " + " ".join(f"{c[0]:>4d}/{c[1]:<3d}" for c in per_kind[n].values()))


def add_predict_arguments(ap, unit):
    """The arguments both study scripts take: --predictors, --delay-frames, --predict-args, --check
    and --jobs (unit names what one run is, "track" or "replay")."""
    ap.add_argument("--delay-frames", type=int, default=2, help="predict's --delay-frames, the horizon in frames (default 2)")
    ap.add_argument("--predictors", default="all", help="predict's --predictor list ([LABEL=]NAME[:KEY=VALUE...]); must include hold")
    ap.add_argument("--predict-args", default="", help="further arguments of predict, e.g. '--fit --fit-split 0.5'")
    ap.add_argument("--check", action="store_true", help=f"exit 1 when some predictor does not beat hold on some {unit}")
    ap.add_argument("--jobs", type=int, default=os.cpu_count() or 1, help=f"{unit}s run at once (default: the cores)")


def rates_and_noise(ap, args):
    """The lists of --rates and --noise; ap.error unless the rates are positive, the noise levels not
    negative, --seeds and --jobs at least 1, and --predictors has hold (every ratio is to hold's)."""
    if not {"all", "hold"} & set(args.predictors.split(",")):
        ap.error(f"--predictors: '{args.predictors}' has no hold (add ',hold': every figure is a ratio to hold's RMSE)")
    try:
        rates = [float(x) for x in args.rates.split(",")]
        noises = [float(x) for x in args.noise.split(",")]
    except ValueError as e:
        ap.error(f"--rates/--noise: {e}")
    if args.seeds < 1 or args.jobs < 1 or args.delay_frames < 0 or any(r <= 0 for r in rates) or any(n < 0 for n in noises):
        ap.error("need --seeds >= 1, --jobs >= 1, --delay-frames >= 0, positive --rates and --noise not negative")
    return rates, noises


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0], formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("bin", help="the predvs binary")
    ap.add_argument("--out", default="out/foreign-tracks", help="output directory of results.csv (default out/foreign-tracks)")
    ap.add_argument("--seed", type=int, default=1, help="first seed S (default 1)")
    ap.add_argument("--seeds", type=int, default=4, help="tracks per cell, seeds S..S+N-1 (default 4)")
    ap.add_argument("--draw", type=int, default=0,
                    help="draw D of the timestamp jitter, dropped frames and noise over the same motions: "
                         "0 = the tracks as before, D > 0 another independent one (default 0)")
    ap.add_argument("--rates", default="10,15,25,30,50,60", help="comma list of frame rates, Hz (default 10,15,25,30,50,60)")
    ap.add_argument("--noise", default="0.5,1,2,3", help="comma list of noise std per coordinate, px (default 0.5,1,2,3)")
    ap.add_argument("--duration-s", type=float, default=15.0, help="track duration, s (default 15)")
    ap.add_argument("--drop", type=float, default=0.03, help="single-frame drop probability; occlusions of 3-10 frames begin at drop/10")
    ap.add_argument("--jitter", type=float, default=0.1, help="timestamp jitter, fraction of a period (uniform +-)")
    ap.add_argument("--kinds", default=",".join(KINDS), help="comma list of motion kinds (default all: " + ",".join(KINDS) + ")")
    ap.add_argument("--keep-tracks", action="store_true", help="also write each track to OUT/tracks/KIND-RATEhz-NOISEpx-SEED.csv")
    add_predict_arguments(ap, "track")
    args = ap.parse_args()
    rates, noises = rates_and_noise(ap, args)
    if args.draw < 0:
        ap.error("--draw: expected an integer >= 0")
    if not args.duration_s > 1.5 or not 0 <= args.drop < 1 or not 0 <= args.jitter < 0.5:
        ap.error("need --duration-s > 1.5, 0 <= --drop < 1 and 0 <= --jitter < 0.5")
    kinds = args.kinds.split(",")
    for k in kinds:
        if k not in KINDS:
            ap.error(f"--kinds: unknown kind '{k}' (known: {', '.join(KINDS)})")
    if not os.access(args.bin, os.X_OK):
        ap.error(f"{args.bin}: not an executable")
    cells = [(k, r, n, s) for k in kinds for r in rates for n in noises for s in range(args.seed, args.seed + args.seeds)]
    if args.keep_tracks:
        os.makedirs(os.path.join(args.out, "tracks"), exist_ok=True)
    try:
        results = run_cells("foreign-tracks", lambda c, work: run_one(args, *c, work), cells, args.jobs)
    except RuntimeError as e:
        print(f"foreign-tracks: error: {e}", file=sys.stderr)
        return 2
    return report(results, args.out, kinds, args.check, args.delay_frames)


def run_cells(prefix, fn, cells, jobs, unit="tracks"):
    """fn(cell, work) for every cell on jobs threads, work a temporary directory (removed after);
    progress on stderr every 50 cells (counted in unit). Returns the results; a RuntimeError of fn is
    raised."""
    work = tempfile.mkdtemp(prefix=prefix + "-")
    results = []
    try:
        with concurrent.futures.ThreadPoolExecutor(max_workers=jobs) as pool:
            futs = [pool.submit(fn, c, work) for c in cells]
            for fut in concurrent.futures.as_completed(futs):
                results.append(fut.result())
                if len(results) % 50 == 0 or len(results) == len(cells):
                    print(f"{len(results)}/{len(cells)} {unit}", file=sys.stderr)
    finally:
        shutil.rmtree(work, ignore_errors=True)
    return results


def report(results, out, kinds, check, delay_frames=2):
    """Writes out/results.csv from results [(kind, rate, noise, seed, {predictor: RMSE vs truth})]
    and prints, per predictor, the tracks where it beats hold, the geometric mean and worst ratio
    (delay_frames ahead, as run), and the comparison with the best fixed KF (print_within_best). Returns the exit status: 1 when
    check and some predictor does not beat hold on some track (one line each on stderr), else 0."""
    results.sort()
    os.makedirs(out, exist_ok=True)
    names = [n for n in results[0][4] if n != "hold"]
    stats = {n: [0, 0.0, 0.0, ""] for n in names}
    losses = []
    tmp = os.path.join(out, ".results.csv")
    with open(tmp, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["kind", "rate_hz", "noise_px", "seed", "predictor", "rmse_truth_px", "ratio_to_hold"])
        for kind, rate, noise, seed, rows in results:
            hold = rows["hold"]
            for n in names:
                ratio = rows[n] / hold
                w.writerow([kind, f"{rate:g}", f"{noise:g}", seed, n, f"{rows[n]:.5f}", f"{ratio:.5f}"])
                st = stats[n]
                st[0] += ratio < 1.0
                st[1] += math.log(ratio)
                if ratio >= 1.0:
                    losses.append(f"{n} does not beat hold on {kind} {rate:g} Hz {noise:g} px #{seed}: x{ratio:.3f}")
                if ratio > st[2]:
                    st[2], st[3] = ratio, f"{kind} {rate:g} Hz {noise:g} px #{seed}"
    os.replace(tmp, os.path.join(out, "results.csv"))
    print(f"{'predictor':16s} {'beats hold':>12s} {'mean ratio':>10s}  worst   (ratio: RMSE vs truth / hold's, {delay_frames} frames ahead; geometric mean)")
    for n in names:
        st = stats[n]
        print(f"{n:16s} {st[0]:5d}/{len(results):<6d} {math.exp(st[1] / len(results)):10.3f}  {st[2]:.3f} ({st[3]})")
    print_within_best(results, names, kinds)
    if check and losses:
        print("\n".join(losses), file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
