#!/bin/bash
# Where `pipescope map` stops holding as the wall's texture fades under noise (docs/conditions.md,
# "Fisheye straight pipe"): the fisheye1 set-up of bench/conditions.sh (001's 190-degree lens in
# the straight 400 mm pipe, one way, 2.1 m, 210 frames) with the target's highlights (specular
# strength 0.6, exponent 80), over texture contrasts and noise sigmas. Prints, per run, the
# distance error and ATE from metrics.json, the verdict and the predicted frames from run.json,
# or the run's error when it failed. A run more than 2 % off that calls itself reliable is marked
# SILENT.
# CONFIG=FILE runs map with that config (say `matcher: lucas-kanade`).
# Usage: CONTRASTS="0.4 0.6 0.8 1" NOISES="1 2 3" SEEDS="1" [CONFIG=FILE]
#        bench/fisheye_texture_sweep.sh [BUILD_DIR] [OUT_DIR]
set -euo pipefail
BUILD_DIR=${1:-build}
OUT=${2:-/tmp/pipescope_fisheye_texture_sweep}
CONTRASTS=${CONTRASTS:-0.4 0.6 0.8 1}
NOISES=${NOISES:-1 2 3}
SEEDS=${SEEDS:-1}
P=$BUILD_DIR/pipescope
CONFIG_ARGS=()
if [ -n "${CONFIG:-}" ]; then CONFIG_ARGS=(--config "$CONFIG"); fi
mkdir -p "$OUT/runs"
SETUP="--preset fiberglass-network --frames 210 --set layout=straight --set length_m=2.7 \
--set end_margin_m=0.3 --set speed_m_s=0.075 --set speed_variation=0.05 --set wander_wavelength_m=2 \
--set specular_strength=0.6 --set specular_exponent=80"
printf '%-8s %-6s %-5s %10s %9s  %s\n' contrast noise seed "distance" "ATE" "verdict"
for seed in $SEEDS; do
  for contrast in $CONTRASTS; do
    for noise in $NOISES; do
      name="c$contrast-n$noise-seed$seed"
      data="$OUT/data/$name"
      run="$OUT/runs/$name"
      if [ ! -f "$data/dataset.yaml" ]; then
        # shellcheck disable=SC2086  # SETUP holds several words
        "$P" simulate $SETUP --set texture_contrast="$contrast" --set noise_sigma="$noise" \
          --seed "$seed" --out "$data" -q
      fi
      if [ ! -f "$run/run.json" ] && [ ! -f "$OUT/runs/$name.failed" ]; then
        "$P" map "$data" --out "$run" "${CONFIG_ARGS[@]}" --no-report -q >/dev/null 2>"$OUT/runs/$name.log" ||
          cp "$OUT/runs/$name.log" "$OUT/runs/$name.failed"
      fi
      if [ -f "$OUT/runs/$name.failed" ]; then
        printf '%-8s %-6s %-5s %10s %9s  failed: %s\n' "$contrast" "$noise" "$seed" - - \
          "$(grep -o 'the run failed: [^;]*' "$OUT/runs/$name.failed" | head -1)"
        continue
      fi
      python3 - "$run" "$contrast" "$noise" "$seed" <<'PY'
import json
import sys

run, contrast, noise, seed = sys.argv[1:]
metrics = json.load(open(f"{run}/metrics.json"))
quality = json.load(open(f"{run}/run.json"))["quality"]
error = metrics["distance_error_pct"]
verdict = quality["verdict"]
silent = "  SILENT" if abs(error) > 2.0 and verdict == "reliable" else ""
print(f"{contrast:8s} {noise:6s} {seed:5s} {error:8.3f} % {1000 * metrics['ate_rmse_m']:6.1f} mm"
      f"  {verdict} ({quality['frames_predicted']} predicted){silent}")
PY
    done
  done
done
