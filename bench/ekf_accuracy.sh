#!/bin/bash
# The tubular EKF (004) through bends and straight pipes (docs/ekf.md): tube-bend at 45, 90 and
# 135 degrees (bend radius 0.5 m) and at 90 degrees with a 1 m bend radius, seed 1 (the 90-degree
# bend at seed 1 is the one the defaults were chosen on; seeds 2 and 3 of it were not looked at
# while choosing), and the straight steel-16in and steel-6in set-ups with the wall-looking
# camera (axis_along_tube: x), where sparse and dense-unrolled run beside it. Prints, per run:
# the distance along the centreline against the truth's, metrics.json's net distance error,
# ATE and orientation error, the bend angle (first to last section), the worst section radius,
# the sections, the odometry's frames per second and the run's verdict. Seed 5 of the 90-degree
# bend and seed 7 of the 45- and 135-degree bends are held out, and so are two harder runs: seed 11
# with texture contrast 0.4, specular strength 0.6 and noise sigma 3, and seed 13 wandering
# 30 mm off the axis (0.3 radii) with 5 degrees of wobble and 10 of roll. Seed 17 of the weak
# texture was added on 2026-11-30, after the bending sections' settings were chosen. The fe190-*
# runs are the same bends through 001's 190-degree fisheye. The new section's look-ahead (one
# radius, 2026-12-01) was chosen on seeds 1-3 of the 90-degree bend of each camera, the flat
# field as an angle and the margin of 1.5 windows (the same day) on the fisheye's seeds 1-3.
# Usage: bench/ekf_accuracy.sh [BUILD_DIR] [OUT_DIR]
set -euo pipefail
BUILD_DIR=${1:-build}
OUT=${2:-/tmp/pipescope_ekf_accuracy}
P=$BUILD_DIR/pipescope
HERE=$(dirname "$0")
mkdir -p "$OUT"

simulate() {  # NAME PRESET ARGS...
  local name=$1 preset=$2
  shift 2
  if [ ! -f "$OUT/$name/dataset.yaml" ]; then
    "$P" simulate --preset "$preset" --out "$OUT/$name" -q "$@"
  fi
}

# The route length sets the frames: 0.05 m/s at 15 fps is 3.33 mm a frame.
simulate bend90 tube-bend --frames 700 --seed 1
simulate bend90-seed2 tube-bend --frames 700 --seed 2
simulate bend90-seed3 tube-bend --frames 700 --seed 3
simulate bend45 tube-bend --frames 620 --seed 1 --set bend_angle_deg=45
simulate bend135 tube-bend --frames 860 --seed 1 --set bend_angle_deg=135
simulate bend90-r1m tube-bend --frames 950 --seed 1 --set bend_radius_m=1.0
# Held out (2026-11-28): no setting was chosen on these.
simulate bend90-seed5 tube-bend --frames 700 --seed 5
simulate bend45-seed7 tube-bend --frames 620 --seed 7 --set bend_angle_deg=45
simulate bend135-seed7 tube-bend --frames 860 --seed 7 --set bend_angle_deg=135
# Held out, harder conditions: weak texture with a sheen and noise; a wider wander.
simulate bend90-weak tube-bend --frames 700 --seed 11 --set texture_contrast=0.4 \
  --set specular_strength=0.6 --set noise_sigma=3
simulate bend90-weak-s17 tube-bend --frames 700 --seed 17 --set texture_contrast=0.4 \
  --set specular_strength=0.6 --set noise_sigma=3
simulate bend90-wander tube-bend --frames 700 --seed 13 --set lateral_offset_m=0.03 \
  --set wobble_deg=5 --set roll_deg=10
# 001's 190-degree fisheye (fisheye-poly) through the same bends; seeds 1-3 of the 90-degree bend
# served to choose the tracker's margin from the image circle's edge (2026-12-01), seed 5 and
# seed 7 of the 45- and 135-degree bends were held out.
FISHEYE=(--set camera_model=fisheye-poly --set fov_deg=190)
simulate fe190-bend90 tube-bend --frames 700 --seed 1 "${FISHEYE[@]}"
simulate fe190-bend90-seed2 tube-bend --frames 700 --seed 2 "${FISHEYE[@]}"
simulate fe190-bend90-seed3 tube-bend --frames 700 --seed 3 "${FISHEYE[@]}"
simulate fe190-bend90-seed5 tube-bend --frames 700 --seed 5 "${FISHEYE[@]}"
simulate fe190-bend45-seed7 tube-bend --frames 620 --seed 7 --set bend_angle_deg=45 "${FISHEYE[@]}"
simulate fe190-bend135-seed7 tube-bend --frames 860 --seed 7 --set bend_angle_deg=135 "${FISHEYE[@]}"
# Held out too, run once after the choice: the 1 m bend radius, the weak texture, the wander.
simulate fe190-bend90-r1m tube-bend --frames 950 --seed 1 --set bend_radius_m=1.0 "${FISHEYE[@]}"
simulate fe190-bend90-weak tube-bend --frames 700 --seed 11 --set texture_contrast=0.4 \
  --set specular_strength=0.6 --set noise_sigma=3 "${FISHEYE[@]}"
simulate fe190-bend90-wander tube-bend --frames 700 --seed 13 --set lateral_offset_m=0.03 \
  --set wobble_deg=5 --set roll_deg=10 "${FISHEYE[@]}"
# A 120-degree Kannala-Brandt camera (added 2026-12-01 after every choice; nothing was chosen on it).
KB=(--set camera_model=kannala-brandt --set fov_deg=120)
simulate kb120-bend90-seed1 tube-bend --frames 700 --seed 1 "${KB[@]}"
simulate kb120-bend90-seed5 tube-bend --frames 700 --seed 5 "${KB[@]}"
simulate kb120-bend135-seed7 tube-bend --frames 860 --seed 7 --set bend_angle_deg=135 "${KB[@]}"
simulate steel-16in steel-16in --frames 400 --seed 1 --set out_and_back=false
simulate steel-6in steel-6in --frames 300 --seed 1

for name in bend90 bend90-seed2 bend90-seed3 bend45 bend135 bend90-r1m bend90-seed5 bend45-seed7 \
  bend135-seed7 bend90-weak bend90-weak-s17 bend90-wander fe190-bend90 fe190-bend90-seed2 \
  fe190-bend90-seed3 fe190-bend90-seed5 fe190-bend45-seed7 fe190-bend135-seed7 fe190-bend90-r1m \
  fe190-bend90-weak fe190-bend90-wander kb120-bend90-seed1 kb120-bend90-seed5 kb120-bend135-seed7; do
  "$P" odometry "$OUT/$name" --method ekf --out "$OUT/run-$name" -q --no-report > /dev/null 2>&1 || true
  python3 "$HERE/ekf_evaluate.py" "$OUT/$name" "$OUT/run-$name" "$name"
done

printf 'axis_along_tube: x\n' > "$OUT/wall.yaml"
for name in steel-16in steel-6in; do
  "$P" odometry "$OUT/$name" --method ekf --config "$OUT/wall.yaml" --out "$OUT/run-$name" -q \
    --no-report > /dev/null 2>&1 || true
  python3 "$HERE/ekf_evaluate.py" "$OUT/$name" "$OUT/run-$name" "$name ekf"
  for method in sparse dense-unrolled; do
    "$P" odometry "$OUT/$name" --method $method --out "$OUT/run-$name-$method" -q --no-report \
      > /dev/null 2>&1 || true
    python3 - "$OUT/run-$name-$method" "$name $method" <<'PY'
import json, sys
run, label = sys.argv[1], sys.argv[2]
m = json.load(open(f"{run}/metrics.json")); r = json.load(open(f"{run}/run.json"))
print(f"{label:28s} net {m['distance_error_pct']:6.3f} %  ATE {1000 * m['ate_rmse_m']:6.1f} mm  "
      f"rot {m['rot_rmse_deg']:5.2f} deg  {r['counts']['frames'] / r['timings_s']['odometry']:5.1f} frames/s")
PY
  done
done
