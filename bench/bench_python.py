#!/usr/bin/env python3
"""The Python API against AllanTools, side by side in one process: the six default statistics
(adev, oadev, mdev, hdev, ohdev, totdev) at the command line's default taus (--taus cli: its
"log:16" grid, 91 taus, given to both as seconds) and at AllanTools' default (--taus octave,
23 taus; --taus both, the default, runs the two one after the other), on one 90-minute 1 kHz
channel (5.4 M fractional-frequency samples), through
allanlot's AllanTools-compatible functions and through AllanTools itself, each repeated
--reps times; the medians, their ratio, and the Python call overhead (a call on 100 samples).

  PYTHONPATH=build/python python3 bench/bench_python.py [--allantools DIR] [--samples N]
                                       [--reps 3] [--threads T] [--taus cli|octave|both]
                                       [--clock wall|cpu] [--all-stats] [--json FILE]

--allantools DIR: a directory holding the package allantools (e.g. a checkout of
github.com/aewallin/allantools; it needs numpy and scipy). Without it, AllanTools is imported
from the path, and when it is absent only allanlot is timed. The results are also checked to
agree (devs within 1e-9 relative): a benchmark of different numbers would mean nothing.
"""
import argparse
import json
import statistics
import sys
import time

import numpy as np

STATS = ("adev", "oadev", "mdev", "hdev", "ohdev", "totdev")
# --all-stats: every statistic, on the 5.4 M-sample channel where AllanTools finishes in
# minutes, on shorter records where its pure-Python loops (O(N m) per tau, or O(N^2) memory for
# MTIE's rolling window) would take hours: the record length is printed with each row.
ALL_STATS = {"adev": None, "oadev": None, "mdev": None, "tdev": None, "hdev": None,
             "ohdev": None, "totdev": None, "tierms": None, "pdev": 20_000, "mtie": 20_000,
             "mtotdev": 2_000, "ttotdev": 2_000, "htotdev": 2_000, "theo1": 2_000}


CLOCK = time.perf_counter


def median_time(f, reps):
    times = []
    for _ in range(reps):
        t0 = CLOCK()
        out = f()
        times.append(CLOCK() - t0)
    return statistics.median(times), out


def run_grid(allanlot, allantools, y, grid, a):
    """Every statistic of the plan on one tau grid: the rows and the six statistics' totals."""
    taus = None
    if grid == "cli":
        # The taus `analyze` evaluates OADEV at on this channel (its default grid and range).
        taus = allanlot.deviation(y, "oadev", 1000.0, "freq", confidence=None).tau
    rows = []
    plan = ALL_STATS if a.all_stats else dict.fromkeys(STATS)
    for stat, n in plan.items():
        x = y if n is None else y[:n]
        ours = getattr(allanlot, stat)
        t_al, r_al = median_time(lambda: ours(x, rate=1000.0, data_type="freq", taus=taus,
                                              threads=a.threads), a.reps)
        row = {"stat": stat, "samples": len(x), "allanlot_s": t_al, "taus": len(r_al[0])}
        if allantools:
            theirs = getattr(allantools, stat)
            t_at, r_at = median_time(lambda: theirs(x, rate=1000.0, data_type="freq", taus=taus),
                                     max(1, a.reps // 3))
            if len(r_at[0]) != len(r_al[0]) or not np.allclose(r_at[1], r_al[1], rtol=1e-9):
                sys.exit("bench_python: %s: allanlot and AllanTools disagree" % stat)
            row.update(allantools_s=t_at, ratio=t_at / t_al)
        rows.append(row)
        print("%-6s %-7s %9d samples %3d taus  allanlot %8.4f s" % (
            grid, stat, len(x), row["taus"], t_al) +
              ("   AllanTools %8.3f s   ratio %6.1f" % (row["allantools_s"], row["ratio"])
               if allantools else ""), flush=True)
    six = [r for r in rows if r["stat"] in STATS]
    out = {"rows": rows, "allanlot_total_s": sum(r["allanlot_s"] for r in six)}
    print("%s taus, six statistics: allanlot %.3f s" % (grid, out["allanlot_total_s"]), end="")
    if allantools:
        total_at = sum(r["allantools_s"] for r in six)
        out.update(allantools_total_s=total_at, ratio=total_at / out["allanlot_total_s"])
        print(", AllanTools %.3f s, ratio %.1f (target >= %d)" % (
            total_at, out["ratio"], 30 if grid == "cli" else 20), end="")
    print(flush=True)
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--allantools", help="directory holding the package allantools")
    ap.add_argument("--samples", type=int, default=5_400_000)
    ap.add_argument("--reps", type=int, default=3)
    ap.add_argument("--threads", type=int, default=None)
    ap.add_argument("--json", help="write the figures to this file")
    # On a shared machine the wall clock measures the neighbours too; the CPU time of this
    # process (all its threads) does not, and with --threads 1 it compares like with like.
    ap.add_argument("--clock", choices=("wall", "cpu"), default="wall")
    ap.add_argument("--taus", choices=("cli", "octave", "both"), default="both")
    ap.add_argument("--all-stats", action="store_true",
                    help="every statistic (shorter records for the slow AllanTools ones)")
    a = ap.parse_args()
    global CLOCK
    CLOCK = time.process_time if a.clock == "cpu" else time.perf_counter
    import allanlot
    if a.allantools:
        sys.path.insert(0, a.allantools)
    try:
        import allantools
    except ImportError:
        allantools = None
    y = np.random.default_rng(1).standard_normal(a.samples) * 1e-9
    grids = ("cli", "octave") if a.taus == "both" else (a.taus,)
    summary = {"samples": a.samples, "threads": a.threads, "clock": a.clock, "grids": {}}
    for grid in grids:
        summary["grids"][grid] = run_grid(allanlot, allantools, y, grid, a)
    small = np.random.default_rng(2).standard_normal(100)
    t_small, _ = median_time(lambda: allanlot.oadev(small, data_type="freq"), 200)
    summary["call_overhead_s"] = t_small
    print("call on 100 samples (octave taus): %.1f us" % (t_small * 1e6))
    if a.json:
        with open(a.json, "w", encoding="utf-8") as f:
            json.dump(summary, f, indent=1)


if __name__ == "__main__":
    main()
