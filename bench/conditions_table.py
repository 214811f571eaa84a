#!/usr/bin/env python3
"""Summarises bench/conditions.sh: per set-up and method, the median and worst distance error and
worst leg error over the tuning seed and, apart, over the held-out seeds; and how many runs ended
more than 2 % off without their run.json calling them unreliable (silent failures).
Usage: conditions_table.py OUT_DIR [TAG] [--markdown]   (writes OUT_DIR/conditions-TAG.csv)
--markdown prints, per set-up, every run's distance error and worst leg (%), "U" marking a run
its run.json called unreliable, and for the "default" method (no --method) the method that ran:
the tables of docs/conditions.md."""
import csv
import glob
import json
import os
import re
import statistics
import sys

TUNING_SEEDS = {1}
SILENT_LIMIT_PCT = 2.0


def load_runs(out, tag):
    rows = []
    for run in sorted(glob.glob(f"{out}/runs/{tag}/*")):
        match = re.match(r"(\w+)-(\w+)-seed(\d+)-(.+)$", os.path.basename(run))
        if not match or not os.path.exists(f"{run}/metrics.json"):
            continue
        setup, condition, seed, method = match.groups()
        m = json.load(open(f"{run}/metrics.json"))
        r = json.load(open(f"{run}/run.json"))
        legs = [m.get(k) for k in ("forward_error_pct", "reverse_error_pct")]
        quality = r.get("quality", {})
        odometry_s = r.get("timings_s", {}).get("odometry")
        rows.append({
            "setup": setup, "condition": condition, "seed": int(seed), "method": method,
            "distance_pct": m["distance_error_pct"],
            "forward_pct": legs[0], "reverse_pct": legs[1],
            "return_pct": m.get("return_error_pct"),
            "ate_mm": 1000 * m["ate_rmse_m"],
            "verdict": quality.get("verdict", "?"),
            "reasons": "; ".join(quality.get("reasons", [])),
            "predicted": m.get("frames_predicted", 0),
            "not_localised": m.get("frames_not_localised", 0),
            "fps": r["counts"]["frames"] / odometry_s if odometry_s else None,
            # The method that ran when the run left the choice to `odometry` ("default").
            "chosen": r.get("method_choice", {}).get("method", ""),
        })
    return rows


def worst_leg(row):
    legs = [abs(v) for v in (row["forward_pct"], row["reverse_pct"]) if v is not None]
    return max(legs) if legs else float("nan")


def summary(rows):
    errors = [abs(r["distance_pct"]) for r in rows]
    legs = [worst_leg(r) for r in rows]
    silent = [r for r in rows if abs(r["distance_pct"]) > SILENT_LIMIT_PCT and
              r["verdict"] == "reliable"]
    worst = max(rows, key=lambda r: abs(r["distance_pct"]))
    return (f"{statistics.median(errors):7.3f} {max(errors):7.3f} {max(legs):7.3f} "
            f"{len(silent):>3}/{len(rows):<3} {worst['condition']}-{worst['seed']}")


def markdown(rows):
    for setup in sorted({r["setup"] for r in rows}):
        mine = [r for r in rows if r["setup"] == setup]
        columns = sorted({(r["seed"], r["condition"]) for r in mine})
        print(f"\n{setup}: distance / worst leg, % (U: run.json says unreliable)\n")
        print("| method | " + " | ".join(f"{c} s{s}" for s, c in columns) + " |")
        print("|---|" + "---|" * len(columns))
        for method in sorted({r["method"] for r in mine}):
            cells = []
            for seed, condition in columns:
                run = [r for r in mine if r["method"] == method and r["seed"] == seed and
                       r["condition"] == condition]
                if not run:
                    cells.append("–")
                    continue
                r = run[0]
                leg = worst_leg(r)
                text = f"{abs(r['distance_pct']):.3f}"
                if leg == leg:  # not NaN
                    text += f" / {leg:.2f}"
                text += " U" if r["verdict"] != "reliable" else ""
                cells.append(text + (f" ({r['chosen']})" if method == "default" else ""))
            print(f"| {method} | " + " | ".join(cells) + " |")


def main():
    out = sys.argv[1]
    tag = sys.argv[2] if len(sys.argv) > 2 and not sys.argv[2].startswith("--") else "default"
    rows = load_runs(out, tag)
    if not rows:
        sys.exit(f"no runs under {out}/runs/{tag}")
    if "--markdown" in sys.argv:
        markdown(rows)
        return
    with open(f"{out}/conditions-{tag}.csv", "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        writer.writeheader()
        writer.writerows(rows)
    print(f"runs: {out}/runs/{tag}  (|errors| in %; silent = more than {SILENT_LIMIT_PCT} % off "
          "yet 'reliable'; worst = the condition and seed of the worst distance error)")
    header = f"{'median':>7} {'worst':>7} {'leg':>7} {'silent':>7} {'worst at':<12}"
    for setup in sorted({r["setup"] for r in rows}):
        print(f"\n{setup}: {'method':<15} | tuning seed {sorted(TUNING_SEEDS)}: {header} | "
              f"held-out seeds: {header} | frames/s")
        for method in sorted({r["method"] for r in rows if r["setup"] == setup}):
            mine = [r for r in rows if r["setup"] == setup and r["method"] == method]
            tuning = [r for r in mine if r["seed"] in TUNING_SEEDS]
            held = [r for r in mine if r["seed"] not in TUNING_SEEDS]
            fps = [r["fps"] for r in mine if r["fps"]]
            cells = [summary(group) if group else f"{'-':>43}" for group in (tuning, held)]
            speed = f"{statistics.median(fps):8.1f}" if fps else "-"
            print(f"{'':{len(setup) + 2}}{method:<15} | {' ' * 13}{cells[0]} | "
                  f"{' ' * 16}{cells[1]} | {speed}")


if __name__ == "__main__":
    main()
