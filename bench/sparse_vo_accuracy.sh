#!/bin/bash
# Distance and return errors (000 eq. 50-51), ATE and speed of `pipescope odometry --method
# sparse` on the simulated steel pipes of 000 Table 1, for docs/sparse_vo.md. The frames are
# simulated once per set-up (steel-6in: 2 m one way, 1460 frames at 1024x768; steel-16in: the
# full forward-and-reverse run, 2392 frames at 640x480; steel-6in-return: steel-6in 2 m out and
# 2 m back, 3010 frames, for the return error) and kept in OUT_DIR; the same seed gives the same
# frames as bench/dense_vo_accuracy.sh, so its folders can be linked in. PRESETS="..." picks.
# Usage: bench/sparse_vo_accuracy.sh [BUILD_DIR] [OUT_DIR] [SEED] [CONFIG.yaml]
set -euo pipefail
BUILD_DIR=${1:-build}
OUT=${2:-/tmp/pipescope_sparse_vo}
SEED=${3:-1}
CONFIG=${4:-}
P=$BUILD_DIR/pipescope
declare -A FRAMES=([steel-6in]=1460 [steel-16in]=2392 [steel-6in-return]=3010)
# steel-6in's travel is length_m less its two 0.0778 m end margins.
declare -A EXTRA=([steel-6in-return]="--set out_and_back=true --set length_m=2.1556")
mkdir -p "$OUT/runs"
TAG=default
CONFIG_ARGS=()
if [ -n "$CONFIG" ]; then
  TAG=$(basename "$CONFIG" .yaml)
  CONFIG_ARGS=(--config "$CONFIG")
fi
printf "%-11s %-10s %9s %9s %9s %9s %9s %9s %8s\n" preset config dist_err forward reverse \
  return ate_mm ate_max frames/s
for preset in ${PRESETS:-steel-6in steel-16in steel-6in-return}; do
  data="$OUT/$preset-seed$SEED"
  if [ ! -f "$data/dataset.yaml" ]; then
    # shellcheck disable=SC2086  # EXTRA holds several words
    "$P" simulate --preset "${preset%-return}" --frames "${FRAMES[$preset]}" --seed "$SEED" \
      ${EXTRA[$preset]:-} --out "$data" -q
  fi
  run="$OUT/runs/$preset-seed$SEED-sparse-$TAG"
  "$P" odometry "$data" --method sparse --out "$run" -q "${CONFIG_ARGS[@]}" >/dev/null
  python3 - "$preset" "$TAG" "$run" <<'PY'
import json, sys
preset, tag, run = sys.argv[1:4]
m = json.load(open(f"{run}/metrics.json"))
r = json.load(open(f"{run}/run.json"))
def pct(key):
    return "-" if m.get(key) is None else f"{m[key]:.3f}"
fps = r["counts"]["frames"] / r["timings_s"]["odometry"]
print(f"{preset:<11} {tag:<10} {pct('distance_error_pct'):>9} {pct('forward_error_pct'):>9} "
      f"{pct('reverse_error_pct'):>9} {pct('return_error_pct'):>9} {1000 * m['ate_rmse_m']:9.2f} "
      f"{1000 * m['ate_max_m']:9.2f} {fps:8.1f}")
PY
done
