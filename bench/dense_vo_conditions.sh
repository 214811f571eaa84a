#!/bin/bash
# Dense odometry on degraded frames (docs/dense_vo.md, "Dark, blurred, flat and stopping"): the
# steel-16in set-up, one way for 900 frames, simulated once per condition with the same seed and
# trajectory, then every method. Prints the signed distance error (000 eq. 50), the same after
# the floor (what the robot's drift and tilt give a method that follows the image motion exactly,
# bench/dense_vo_floor.py), and the failed pairs.
# Usage: bench/dense_vo_conditions.sh [BUILD_DIR] [OUT_DIR] [SEED]
set -euo pipefail
BUILD_DIR=${1:-build}
OUT=${2:-/tmp/pipescope_dense_conditions}
SEED=${3:-7}
P=$BUILD_DIR/pipescope
HERE=$(dirname "$0")
METHODS="dense-sad dense-ssd dense-zncc dense-lk dense-hybrid phase dense-unrolled opencv-phase"
declare -A SETTINGS=(
  [base]=""
  [dark]="exposure_target=40 noise_sigma=2"
  [blur]="motion_blur_samples=8 exposure_time_s=0.03"
  [flat]="texture_contrast=0.25"
  [stops]="stop_count=3"
)
CONDITIONS="base dark blur flat stops"
mkdir -p "$OUT"
for condition in $CONDITIONS; do
  data="$OUT/$condition"
  if [ ! -f "$data/dataset.yaml" ]; then
    sets=()
    for setting in ${SETTINGS[$condition]}; do sets+=(--set "$setting"); done
    "$P" simulate --preset steel-16in --frames 900 --seed "$SEED" "${sets[@]}" --out "$data" -q
  fi
  for method in $METHODS; do
    "$P" odometry "$data" --method "$method" --out "$OUT/runs/$condition-$method" -q >/dev/null
  done
done
python3 - "$HERE" "$OUT" "$CONDITIONS" "$METHODS" <<'PY'
import json, sys
sys.path.insert(0, sys.argv[1])
from dense_vo_floor import floor_terms
out, conditions, methods = sys.argv[2], sys.argv[3].split(), sys.argv[4].split()
print("signed distance error % / after the floor % / failed pairs")
print(f"{'condition':10} {'floor':>7} " + " ".join(f"{m:>21}" for m in methods))
for condition in conditions:
    floor = floor_terms(f"{out}/{condition}")["together"]
    cells = []
    for method in methods:
        run = f"{out}/runs/{condition}-{method}"
        m = json.load(open(f"{run}/metrics.json"))
        failed = json.load(open(f"{run}/run.json"))["counts"]["pairs_failed"]
        error = 100 * (m["distance_est_m"] - m["distance_gt_m"]) / m["distance_gt_m"]
        cells.append(f"{error:+.3f} {error - floor:+.3f} {failed:>3}")
    print(f"{condition:10} {floor:+7.3f} " + " ".join(f"{c:>21}" for c in cells))
PY
