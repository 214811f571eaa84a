#!/usr/bin/env python3
"""Dense odometry over several seeds, each method against the OpenCV baseline (docs/dense_vo.md).

For every preset and method: the signed distance error per seed (estimate longer than the truth
is positive, from metrics.json), its mean and worst magnitude, the mean |error - floor| (the error
the method adds to what no planar method observes: drift floor, plus the tilt term on one-way
runs, from bench/dense_vo_floor.py), the mean return error, and the paired comparison with the
baseline on the same frames: the mean over seeds of |error| - |baseline's error| and of the same
after the floor, with their standard errors (negative: below the baseline).

Usage: bench/dense_vo_compare.py OUT_DIR "SEEDS" [--runs PATTERN] [--data PATTERN]
  PATTERN fields: {out} {preset} {seed} {method}; by default the layout of
  bench/dense_vo_accuracy.sh: runs {out}/runs/{preset}-seed{seed}-{method}, data {out}/{preset}-seed{seed}.
"""
import argparse
import json
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from dense_vo_floor import floor_terms  # noqa: E402

PRESETS = ["steel-6in", "steel-16in"]
METHODS = ["dense-sad", "dense-ssd", "dense-zncc", "dense-lk", "dense-hybrid", "phase",
           "dense-unrolled", "opencv-phase"]
BASELINE = "opencv-phase"


def mean(values):
    return sum(values) / len(values)


def paired(values):
    """The mean difference, with its standard error when there are two seeds or more."""
    if not values:
        return ""
    m = mean(values)
    if len(values) < 2:
        return f"{m:+.4f}"
    error = math.sqrt(sum((v - m) ** 2 for v in values) / (len(values) - 1) / len(values))
    return f"{m:+.4f}±{error:.4f}"


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("out")
    parser.add_argument("seeds")
    parser.add_argument("--runs", default="{out}/runs/{preset}-seed{seed}-{method}")
    parser.add_argument("--data", default="{out}/{preset}-seed{seed}")
    args = parser.parse_args()
    seeds = args.seeds.split()
    for preset in PRESETS:
        floors, signed, returns = {}, {}, {}
        for seed in seeds:
            data = args.data.format(out=args.out, preset=preset, seed=seed)
            if not os.path.isfile(f"{data}/dataset.yaml"):
                continue
            floor, tilt, *_ = floor_terms(data)
            floors[seed] = floor + (tilt or 0.0)
            for method in METHODS:
                run = args.runs.format(out=args.out, preset=preset, seed=seed, method=method)
                if not os.path.isfile(f"{run}/metrics.json"):
                    continue
                m = json.load(open(f"{run}/metrics.json"))
                signed[(method, seed)] = 100 * (m["distance_est_m"] / m["distance_gt_m"] - 1)
                if m.get("return_error_pct") is not None:
                    returns[(method, seed)] = m["return_error_pct"]
        if not floors:
            continue
        print(f"\n{preset}: floor per seed (drift floor + tilt term on one-way runs, %): " +
              " ".join(f"{s}:{floors[s]:+.3f}" for s in seeds if s in floors))
        print(f"{'method':<15} {'seeds':>5} {'mean':>7} {'worst':>7} {'-floor':>7} {'return':>7} "
              f"{'vs base':>16} {'-floor vs base':>16}  signed per seed")
        for method in METHODS:
            have = [s for s in seeds if (method, s) in signed]
            if not have:
                continue
            errors = [signed[(method, s)] for s in have]
            beyond = [abs(signed[(method, s)] - floors[s]) for s in have]
            rets = [returns[(method, s)] for s in have if (method, s) in returns]
            with_baseline = [s for s in have if (BASELINE, s) in signed]
            diff = [abs(signed[(method, s)]) - abs(signed[(BASELINE, s)]) for s in with_baseline]
            diff_floor = [abs(signed[(method, s)] - floors[s]) -
                          abs(signed[(BASELINE, s)] - floors[s]) for s in with_baseline]
            versus = paired(diff) if method != BASELINE else ""
            versus_floor = paired(diff_floor) if method != BASELINE else ""
            print(f"{method:<15} {len(have):>5} {mean([abs(e) for e in errors]):7.4f} "
                  f"{max(abs(e) for e in errors):7.4f} {mean(beyond):7.4f} "
                  f"{(f'{mean(rets):.4f}' if rets else '-'):>7} {versus:>16} {versus_floor:>16}  " +
                  " ".join(f"{e:+.3f}" for e in errors))


if __name__ == "__main__":
    main()
