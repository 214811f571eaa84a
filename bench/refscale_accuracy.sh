#!/bin/bash
# Accuracy of `pipescope refscale` on the simulated reference-scale target (000 §3.3), per
# set-up and frame: true and measured zeta, the error, and the error of the paper's plain mean
# of neighbour spacings. Results are recorded in docs/reference_scale.md.
# Usage: bench/refscale_accuracy.sh [BUILD_DIR] [OUT_DIR]
set -euo pipefail
BUILD_DIR=${1:-build}
OUT=${2:-/tmp/pipescope_refscale}
P=$BUILD_DIR/pipescope
declare -A SETUPS=(
  [steel-6in]=""
  [steel-16in]="--set radius_m=0.19378 --set width=640 --set height=480 --set fov_deg=25 --set led_ring_radius_m=0.03"
  [6in-kannala-brandt]="--set camera_model=kannala-brandt"
  [6in-fisheye-poly-70]="--set camera_model=fisheye-poly"
  [6in-fisheye-poly-190]="--set camera_model=fisheye-poly --set fov_deg=190"
)
printf "%-22s %-6s %10s %10s %9s %9s\n" set-up frame truth zeta error plain_mean
for name in steel-6in steel-16in 6in-kannala-brandt 6in-fisheye-poly-70 6in-fisheye-poly-190; do
  # shellcheck disable=SC2086
  "$P" simulate --preset scale-target --out "$OUT/$name" ${SETUPS[$name]} -q
  truth=$(awk '/^reference_scale_px_per_m/ {print $2}' "$OUT/$name/dataset.yaml")
  for image in "$OUT/$name"/images/*.png; do
    "$P" refscale "$image" --camera "$OUT/$name/camera.yaml" --grid 5x4 --spacing-m 0.01 -q |
      awk -v name="$name" -v frame="$(basename "$image" .png)" -v truth="$truth" '
        /^reference_scale_px_per_m/ {z = $2} /^mean_spacing_px_per_m/ {m = $2}
        END {printf "%-22s %-6s %10.2f %10.2f %+8.4f%% %+8.3f%%\n", name, frame, truth, z,
             100 * (z / truth - 1), 100 * (m / truth - 1)}'
  done
done
