#!/usr/bin/env python3
"""Dense odometry over several seeds, each method against the OpenCV baseline (docs/dense_vo.md).

For every preset and method: the signed distance error per seed (estimate longer than the truth
is positive, from metrics.json), its mean and worst magnitude, the mean |error - floor| (the error
the method adds to what no planar method observes: the robot's drift across the pipe and its
tilt, bench/dense_vo_floor.py), and the paired comparison with the baseline on the same frames:
the mean over seeds of |error| - |baseline's error| and of the same after the floor, with their
standard errors (negative: below the baseline). Out-and-back runs also get the return error
(000 eq. 51, from the trajectories) and its mean |return - return floor|, with the same paired
comparison.

Usage: bench/dense_vo_compare.py OUT_DIR "SEEDS" [--runs PATTERN] [--data PATTERN] [--markdown]
  PATTERN fields: {out} {preset} {seed} {method}; by default bench/dense_vo_accuracy.sh's layout:
  runs {out}/runs/{preset}-seed{seed}-{method}, data {out}/{preset}-seed{seed}.
  --markdown prints the rows of docs/dense_vo.md's table instead.
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


def paired(values, digits=4):
    """The mean difference, with its standard error when there are two seeds or more."""
    if not values:
        return ""
    m = mean(values)
    if len(values) < 2:
        return f"{m:+.{digits}f}"
    error = math.sqrt(sum((v - m) ** 2 for v in values) / (len(values) - 1) / len(values))
    return f"{m:+.{digits}f} ± {error:.{digits}f}"


def beyond(table, floor, method, seed):
    """|error - floor| of one method on one seed."""
    return abs(table[(method, seed)] - floor[seed])


def optional(value):
    return "" if value is None else f"{value:.4f}"


def positions(path):
    return [list(map(float, line.split()[1:4])) for line in open(path)
            if line.strip() and not line.startswith("#")]


def signed_return(run, data):
    """Signed eq. 51 in %: ((forward - reverse)_est - (forward - reverse)_gt) / path, the legs
    split at the ground truth's frame farthest from its start (both files have every frame)."""
    gt = positions(f"{data}/groundtruth.tum")
    est = positions(f"{run}/trajectory.tum")
    if len(est) != len(gt):
        return None
    turn = max(range(len(gt)), key=lambda i: abs(gt[i][2] - gt[0][2]))
    forward_gt, reverse_gt = math.dist(gt[0], gt[turn]), math.dist(gt[turn], gt[-1])
    forward_est, reverse_est = math.dist(est[0], est[turn]), math.dist(est[turn], est[-1])
    return 100 * ((forward_est - reverse_est) - (forward_gt - reverse_gt)) / (forward_gt +
                                                                               reverse_gt)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("out")
    parser.add_argument("seeds")
    parser.add_argument("--runs", default="{out}/runs/{preset}-seed{seed}-{method}")
    parser.add_argument("--data", default="{out}/{preset}-seed{seed}")
    parser.add_argument("--markdown", action="store_true")
    args = parser.parse_args()
    seeds = args.seeds.split()
    for preset in PRESETS:
        floors, return_floors, signed, returns = {}, {}, {}, {}
        for seed in seeds:
            data = args.data.format(out=args.out, preset=preset, seed=seed)
            if not os.path.isfile(f"{data}/dataset.yaml"):
                continue
            terms = floor_terms(data)
            floors[seed] = terms["together"]
            if "return_floor" in terms:
                return_floors[seed] = terms["return_floor"]
            for method in METHODS:
                run = args.runs.format(out=args.out, preset=preset, seed=seed, method=method)
                if not os.path.isfile(f"{run}/metrics.json"):
                    continue
                m = json.load(open(f"{run}/metrics.json"))
                signed[(method, seed)] = 100 * (m["distance_est_m"] / m["distance_gt_m"] - 1)
                if seed in return_floors:
                    value = signed_return(run, data)
                    if value is not None:
                        returns[(method, seed)] = value
        if not floors:
            continue
        have_floor = [s for s in seeds if s in floors]
        rows = []
        for method in METHODS:
            have = [s for s in seeds if (method, s) in signed]
            if not have:
                continue
            errors = [signed[(method, s)] for s in have]
            base = [s for s in have if (BASELINE, s) in signed and method != BASELINE]
            ret = [s for s in have if (method, s) in returns]
            ret_base = [s for s in ret if (BASELINE, s) in returns and method != BASELINE]
            rows.append({
                "method": method, "seeds": len(have), "errors": errors,
                "mean": mean([abs(e) for e in errors]), "worst": max(abs(e) for e in errors),
                "beyond": mean([beyond(signed, floors, method, s) for s in have]),
                "versus": paired([abs(signed[(method, s)]) - abs(signed[(BASELINE, s)])
                                  for s in base]),
                "versus_floor": paired([beyond(signed, floors, method, s) -
                                        beyond(signed, floors, BASELINE, s) for s in base]),
                "return": mean([abs(returns[(method, s)]) for s in ret]) if ret else None,
                "return_beyond": (mean([beyond(returns, return_floors, method, s) for s in ret])
                                  if ret else None),
                "return_versus_floor": paired([beyond(returns, return_floors, method, s) -
                                               beyond(returns, return_floors, BASELINE, s)
                                               for s in ret_base]),
            })
        if args.markdown:
            floor_values = [floors[s] for s in have_floor]
            cells = [preset, "floor", f"{mean([abs(v) for v in floor_values]):.4f}",
                     f"{max(abs(v) for v in floor_values):.4f}", "", "", "",
                     optional(mean([abs(return_floors[s]) for s in have_floor])
                         if return_floors else None), "", ""]
            print("| " + " | ".join(cells + [f"{v:+.3f}" for v in floor_values]) + " |")
            for r in rows:
                cells = [preset, r["method"], f"{r['mean']:.4f}", f"{r['worst']:.4f}",
                         f"{r['beyond']:.4f}", r["versus"], r["versus_floor"], optional(r["return"]),
                         optional(r["return_beyond"]), r["return_versus_floor"]]
                print("| " + " | ".join(cells + [f"{e:+.3f}" for e in r["errors"]]) + " |")
            continue
        print(f"\n{preset}: floor per seed (drift + tilt, %): " +
              " ".join(f"{s}:{floors[s]:+.4f}" for s in have_floor) +
              ("; return floor: " + " ".join(f"{s}:{return_floors[s]:+.4f}" for s in have_floor)
               if return_floors else ""))
        print(f"{'method':<15} {'mean':>7} {'worst':>7} {'-floor':>7} {'vs base':>17} "
              f"{'-floor vs base':>17} {'return':>7} {'-floor':>7} {'-floor vs base':>17}  "
              "signed per seed")
        for r in rows:
            print(f"{r['method']:<15} {r['mean']:7.4f} {r['worst']:7.4f} {r['beyond']:7.4f} "
                  f"{r['versus']:>17} {r['versus_floor']:>17} {optional(r['return']):>7} "
                  f"{optional(r['return_beyond']):>7} {r['return_versus_floor']:>17}  " +
                  " ".join(f"{e:+.3f}" for e in r["errors"]))


if __name__ == "__main__":
    main()
