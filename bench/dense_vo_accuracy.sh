#!/bin/bash
# Distance errors (000 eq. 50-51) and speed of every dense odometry method on the simulated
# steel pipes of 000 Table 1, for docs/dense_vo.md. The frames are simulated once per set-up
# (steel-6in: 2 m one way; steel-16in: the full forward-and-reverse run) and kept in OUT_DIR.
# Usage: bench/dense_vo_accuracy.sh [BUILD_DIR] [OUT_DIR] [SEED]
set -euo pipefail
BUILD_DIR=${1:-build}
OUT=${2:-/tmp/pipescope_dense_vo}
SEED=${3:-1}
P=$BUILD_DIR/pipescope
METHODS="dense-sad dense-ssd dense-zncc dense-lk dense-hybrid phase dense-unrolled opencv-phase"
declare -A FRAMES=([steel-6in]=1460 [steel-16in]=2392)
mkdir -p "$OUT"
# frames/s: end to end (PNG decoding on a read-ahead thread); proc/s: preparing and registering
# only, on one core (the stage timings in run.json).
printf "%-11s %-15s %9s %9s %9s %9s %9s %8s %8s\n" preset method dist_err forward reverse return \
  ate_mm frames/s proc/s
for preset in steel-6in steel-16in; do
  data="$OUT/$preset-seed$SEED"
  if [ ! -f "$data/dataset.yaml" ]; then
    "$P" simulate --preset "$preset" --frames "${FRAMES[$preset]}" --seed "$SEED" --out "$data" -q
  fi
  for method in $METHODS; do
    run="$OUT/runs/$preset-seed$SEED-$method"
    # One core, as the speed target asks.
    OMP_NUM_THREADS=1 OPENCV_FOR_THREADS_NUM=1 \
      "$P" odometry "$data" --method "$method" --out "$run" -q >/dev/null
    python3 - "$preset" "$method" "$run" <<'PY'
import json, sys
preset, method, run = sys.argv[1:4]
m = json.load(open(f"{run}/metrics.json"))
r = json.load(open(f"{run}/run.json"))
def pct(key):
    return "-" if m.get(key) is None else f"{m[key]:.3f}"
t = r["timings_s"]
frames = r["counts"]["frames_localised"]
fps = frames / t["odometry"]
proc = frames / (t["odometry_preparing"] + t["odometry_registering"])
print(f"{preset:<11} {method:<15} {pct('distance_error_pct'):>9} {pct('forward_error_pct'):>9} "
      f"{pct('reverse_error_pct'):>9} {pct('return_error_pct'):>9} {1000 * m['ate_rmse_m']:9.2f} "
      f"{fps:8.1f} {proc:8.1f}")
PY
  done
done
