#!/bin/bash
# Every wall-camera method over a matrix of conditions and seeds (issue 22, docs/conditions.md).
# Each dataset is an out-and-back run of 1 m each way (2 m driven) in which the crawler wanders
# across the pipe by up to 5 % of the radius (lateral_offset_m) with a wavelength of 2 m
# (wander_wavelength_m: a low-frequency random process of the distance driven, so the two legs
# wander differently and neither averages its wander away). Conditions:
#   wander  the preset's look with the wander
#   weak    + texture contrast 0.3, sparse specular spots (strength 0.6, exponent 80), noise 4
#   sheen   + a broad sheen (strength 0.6, exponent 8), contrast 0.5, noise 2, roll and wobble
#             doubled (the culvert: wobble doubled, its roll, already a 10 degree sway, kept)
# Set-ups: wall6 (steel-6in, 1024x768, 70 deg), wall16 (steel-16in, 640x480, 25 deg), culvert
# (003's downward camera with its heading wander, 10 deg, and 30 mm sideways: its preset's own)
# and fisheye (001's forward 190 deg lens in a straight 400 mm pipe, `pipescope map`, 1 cm a
# frame, out and back) and fisheye1 (the same one way, 2.1 m, as the fisheye target).
# "phase-rotation" is phase with phase_rotation: true (003 eq. 7). "default" runs `odometry`
# without --method: what a user gets, the method choice and its fallback included (run.json
# `method_choice` says which ran).
# Seed 1 is the tuning seed; seeds 41 and 43 are held out (never used while changing a method).
# Datasets are kept in OUT_DIR/data and reused; runs go to OUT_DIR/runs; the table is printed by
# bench/conditions_table.py, which also writes OUT_DIR/conditions.csv.
# Usage: bench/conditions.sh [BUILD_DIR] [OUT_DIR]
#   SETUPS="wall6 wall16" CONDITIONS="wander weak sheen" SEEDS="1 41 43" METHODS="..." narrow it;
#   TAG=name keeps the runs of a variant apart (CONFIG_sparse=FILE etc. pass a --config).
set -euo pipefail
BUILD_DIR=${1:-build}
OUT=${2:-/tmp/pipescope_conditions}
P=$BUILD_DIR/pipescope
HERE=$(dirname "$0")
SETUPS=${SETUPS:-wall6 wall16 culvert fisheye}
CONDITIONS=${CONDITIONS:-wander weak sheen}
SEEDS=${SEEDS:-1 41 43}
METHODS=${METHODS:-sparse dense-sad dense-ssd dense-zncc dense-lk dense-hybrid phase \
dense-unrolled opencv-phase phase-rotation ekf}
TAG=${TAG:-default}
# steel-6in: 1.373 mm a frame; travel is length_m less two 0.0778 m end margins.
declare -A SETUP_ARGS=(
  [wall6]="--preset steel-6in --frames 1480 --set out_and_back=true --set length_m=1.1556 \
--set lateral_offset_m=0.00383 --set wander_wavelength_m=2"
  [wall16]="--preset steel-16in --frames 720 --set length_m=1.2 --set end_margin_m=0.1 \
--set lateral_offset_m=0.00969 --set wander_wavelength_m=2"
  [culvert]="--preset culvert --frames 620 --set out_and_back=true --set length_m=1.6"
  [fisheye]="--preset fiberglass-network --frames 210 --set layout=straight --set length_m=1.6 \
--set end_margin_m=0.3 --set out_and_back=true --set speed_m_s=0.075 --set speed_variation=0.05 \
--set wander_wavelength_m=2"
  [fisheye1]="--preset fiberglass-network --frames 210 --set layout=straight --set length_m=2.7 \
--set end_margin_m=0.3 --set speed_m_s=0.075 --set speed_variation=0.05 --set wander_wavelength_m=2"
)
declare -A DOUBLE_MOTION=([wall6]="--set roll_deg=2 --set wobble_deg=1"
  [wall16]="--set roll_deg=2 --set wobble_deg=1" [culvert]="--set wobble_deg=1"
  [fisheye]="--set roll_deg=4 --set wobble_deg=2" [fisheye1]="--set roll_deg=4 --set wobble_deg=2")
declare -A CONDITION_ARGS=(
  [wander]=""
  [weak]="--set texture_contrast=0.3 --set specular_strength=0.6 --set specular_exponent=80 \
--set noise_sigma=4"
  [sheen]="--set texture_contrast=0.5 --set specular_strength=0.6 --set specular_exponent=8 \
--set noise_sigma=2"
)
mkdir -p "$OUT/data" "$OUT/runs"
for seed in $SEEDS; do
  for setup in $SETUPS; do
    for condition in $CONDITIONS; do
      data="$OUT/data/$setup-$condition-seed$seed"
      if [ ! -f "$data/dataset.yaml" ]; then
        extra=${CONDITION_ARGS[$condition]}
        [ "$condition" = sheen ] && extra="$extra ${DOUBLE_MOTION[$setup]}"
        # shellcheck disable=SC2086  # the argument strings hold several words
        "$P" simulate ${SETUP_ARGS[$setup]} $extra --seed "$seed" --out "$data" -q
      fi
      methods=$METHODS
      [[ "$setup" == fisheye* ]] && methods=map
      for method in $methods; do
        run="$OUT/runs/$TAG/$setup-$condition-seed$seed-$method"
        [ -f "$run/metrics.json" ] && continue
        config_var="CONFIG_${method//-/_}"
        config_args=()
        [ -n "${!config_var:-}" ] && config_args=(--config "${!config_var}")
        command=(odometry "$data" --method "$method")
        [ "$method" = map ] && command=(map "$data")
        [ "$method" = default ] && command=(odometry "$data")
        if [ "$method" = phase-rotation ]; then
          [ -f "$OUT/phase-rotation.yaml" ] || echo "phase_rotation: true" >"$OUT/phase-rotation.yaml"
          command=(odometry "$data" --method phase)
          config_args=(--config "$OUT/phase-rotation.yaml")
        fi
        "$P" "${command[@]}" --out "$run" --no-report -q "${config_args[@]}" >/dev/null \
          2>"$OUT/runs/$TAG-last.log" || echo "failed: $run" >&2
      done
    done
  done
done
python3 "$HERE/conditions_table.py" "$OUT" "$TAG"
