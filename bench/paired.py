#!/usr/bin/env python3
"""Paired whole-process timing of two commands (standard library only).

  python3 bench/paired.py --pairs 10 [--warmup 1] [--json FILE] --a 'CMD A' --b 'CMD B'

Runs A and B in turn (A B A B ...) after the warm-up pairs, each as a whole process (no shell;
output thrown away), and prints the median and range of wall, CPU (user + system, from wait4)
and peak RSS of each, and of the ratios A/B taken pair by pair (the ratio holds when the machine's
speed drifts during the run).
"""
import argparse
import json
import os
import shlex
import statistics
import subprocess
import sys
import time


def run(argv):
    t0 = time.monotonic()
    p = subprocess.Popen(argv, stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL,
                         stderr=subprocess.DEVNULL)
    _, status, ru = os.wait4(p.pid, 0)
    wall = time.monotonic() - t0
    p.returncode = os.waitstatus_to_exitcode(status)
    if p.returncode != 0:
        sys.exit(f"paired.py: {shlex.join(argv)} exited {p.returncode}")
    return {"wall": wall, "cpu": ru.ru_utime + ru.ru_stime, "peakMiB": ru.ru_maxrss / 1024}


def spread(xs):
    return {"median": statistics.median(xs), "min": min(xs), "max": max(xs)}


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--a", required=True)
    ap.add_argument("--b", required=True)
    ap.add_argument("--pairs", type=int, default=10)
    ap.add_argument("--warmup", type=int, default=1)
    ap.add_argument("--json")
    o = ap.parse_args()
    a, b = shlex.split(o.a), shlex.split(o.b)
    for _ in range(o.warmup):
        run(a)
        run(b)
    ra, rb = [], []
    for _ in range(o.pairs):
        ra.append(run(a))
        rb.append(run(b))
    res = {"a": o.a, "b": o.b, "pairs": o.pairs}
    for k in ("wall", "cpu", "peakMiB"):
        res[f"a_{k}"] = spread([r[k] for r in ra])
        res[f"b_{k}"] = spread([r[k] for r in rb])
    for k in ("wall", "cpu"):
        res[f"ratio_{k}"] = spread([x[k] / y[k] for x, y in zip(ra, rb)])
    print(f"pairs {o.pairs}: A wall {res['a_wall']['median']:.2f} s, B wall "
          f"{res['b_wall']['median']:.2f} s, A/B wall {res['ratio_wall']['median']:.2f} "
          f"({res['ratio_wall']['min']:.2f}-{res['ratio_wall']['max']:.2f}), A/B cpu "
          f"{res['ratio_cpu']['median']:.2f}, peak {res['a_peakMiB']['median']:.0f} / "
          f"{res['b_peakMiB']['median']:.0f} MiB", file=sys.stderr)
    if o.json:
        with open(o.json, "w") as f:
            json.dump(res, f, indent=1)


if __name__ == "__main__":
    main()
