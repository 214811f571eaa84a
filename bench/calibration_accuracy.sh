#!/bin/bash
# Accuracy of `pipescope calibrate` on simulated checkerboard views (issue 4, 001 §II), per
# set-up: views used, focal-length error (fx and fy, or k1), principal-point error, RMS and the
# largest corner angle. Results are recorded in docs/calibration.md.
# Usage: bench/calibration_accuracy.sh [BUILD_DIR] [OUT_DIR] [SEED]
set -euo pipefail
BUILD_DIR=${1:-build}
OUT=${2:-/tmp/pipescope_calibration}
SEED=${3:-1}
P=$BUILD_DIR/pipescope
NAMES=(pinhole-70 pinhole-100 pinhole-70-640 kannala-brandt-150 kannala-brandt-120-640
       fisheye-poly-190 fisheye-poly-220 fisheye-poly-190-800)
declare -A SETUPS=(
  [pinhole-70]="pinhole-radtan"
  [pinhole-100]="pinhole-radtan --set fov_deg=100"
  [pinhole-70-640]="pinhole-radtan --set width=640 --set height=480"
  [kannala-brandt-150]="kannala-brandt --set fov_deg=150"
  [kannala-brandt-120-640]="kannala-brandt --set fov_deg=120 --set width=640 --set height=480"
  [fisheye-poly-190]="fisheye-poly --set fov_deg=190 --set width=1280 --set height=960"
  [fisheye-poly-220]="fisheye-poly --set fov_deg=220 --set width=1280 --set height=960"
  [fisheye-poly-190-800]="fisheye-poly --set fov_deg=190 --set width=800 --set height=600"
)
# The numbers of `params: [a, b, ...]` in a camera.yaml, one a line.
params() { sed -n 's/^params: \[\(.*\)\]/\1/p' "$1" | tr ',' '\n'; }
printf "%-24s %5s %9s %8s %8s %9s\n" set-up views focal_% pp_px rms_px max_deg
for name in "${NAMES[@]}"; do
  read -r model settings <<<"${SETUPS[$name]} "
  # shellcheck disable=SC2086
  "$P" simulate --preset checkerboard --seed "$SEED" --set camera_model="$model" $settings \
    --out "$OUT/$name" -q
  "$P" calibrate --model "$model" --board 9x6 --square-m 0.025 "$OUT/$name/images" \
    --out "$OUT/$name-fit/camera.yaml" -q >/dev/null
  report=$OUT/$name-fit/calibration.json
  paste <(params "$OUT/$name/camera.yaml") <(params "$OUT/$name-fit/camera.yaml") |
    awk -v name="$name" -v model="$model" \
      -v views="$(grep -c '"image"' "$report")" \
      -v rms="$(sed -n 's/^  "rms_px": \([0-9.e-]*\),*$/\1/p' "$report")" \
      -v max_angle="$(sed -n 's/^  "max_angle_deg": \([0-9.e-]*\),*$/\1/p' "$report")" '
      function abs(x) { return x < 0 ? -x : x }
      { t[NR] = $1; f[NR] = $2 }
      END {
        if (model == "fisheye-poly") { focal = abs(f[1] / t[1] - 1); pu = 5 }
        else { focal = abs(f[1] / t[1] - 1); if (abs(f[2] / t[2] - 1) > focal) focal = abs(f[2] / t[2] - 1); pu = 3 }
        pp = sqrt((f[pu] - t[pu]) ^ 2 + (f[pu + 1] - t[pu + 1]) ^ 2)
        printf "%-24s %5d %9.3f %8.2f %8.3f %9.1f\n", name, views, 100 * focal, pp, rms, max_angle
      }'
done
