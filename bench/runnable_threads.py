#!/usr/bin/env python3
"""How busy a command keeps the cores: every ~5 ms, the number of its threads (and its children's,
e.g. gnuplot) in state R (running or runnable), from /proc/PID/task/*/stat; printed per 250 ms as
the mean count, with the share of samples below `--cores` (an idle core, unless another process
took it). Used for docs/PERFORMANCE.md "predict throughput", fourth pass:

    python3 bench/runnable_threads.py build/app/predvs predict --input big.csv --predictor all \
        --delay-frames 2 --out out/big

On a loaded machine the counts still show where predvs had fewer runnable threads than cores
(serial parts, waits); wall times there say little.
"""
import os
import subprocess
import sys
import time


def thread_states(pid):
    states = []
    try:
        for tid in os.listdir(f"/proc/{pid}/task"):
            try:
                stat = open(f"/proc/{pid}/task/{tid}/stat").read()
                states.append(stat[stat.rindex(")") + 2])
            except OSError:
                pass
    except OSError:
        pass
    return states


def children(pid):
    kids = []
    try:
        for tid in os.listdir(f"/proc/{pid}/task"):
            try:
                kids += [int(x) for x in open(f"/proc/{pid}/task/{tid}/children").read().split()]
            except OSError:
                pass
    except OSError:
        pass
    return kids


def main():
    args = sys.argv[1:]
    cores = 2
    if len(args) >= 2 and args[0] == "--cores":
        cores, args = int(args[1]), args[2:]
    if not args:
        sys.exit("usage: runnable_threads.py [--cores N] COMMAND [ARGS...]")
    proc = subprocess.Popen(args, stdout=subprocess.DEVNULL)
    t0 = time.time()
    samples = []  # (time, runnable, threads)
    while proc.poll() is None:
        pids = [proc.pid]
        i = 0
        while i < len(pids):
            pids += children(pids[i])
            i += 1
        states = [s for p in pids for s in thread_states(p)]
        samples.append((time.time() - t0, sum(1 for s in states if s == "R"), len(states)))
        time.sleep(0.005)
    wall = time.time() - t0
    bucket = 0.25
    for k in range(int(wall / bucket) + 1):
        part = [s for s in samples if k * bucket <= s[0] < (k + 1) * bucket]
        if not part:
            continue
        mean = sum(s[1] for s in part) / len(part)
        print(f"{k * bucket:6.2f}-{(k + 1) * bucket:6.2f} s  runnable {mean:4.2f}  threads {max(s[2] for s in part):2d}  "
              + "#" * int(round(mean * 10)))
    below = sum(1 for s in samples if s[1] < cores) / max(1, len(samples))
    print(f"wall {wall:.2f} s; exit status {proc.returncode}; samples with fewer than {cores} runnable: {below:.0%}")
    sys.exit(proc.returncode)


if __name__ == "__main__":
    main()
