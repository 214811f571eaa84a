#!/bin/bash
# The dense benchmark (bench/dense_vo_accuracy.sh) over several seeds: one seed's figures at
# hundredths of a per cent depend on the texture and on where key frames fall, so methods are
# ranked by the mean and the worst distance error over seeds, and compared with the baseline
# seed by seed (bench/dense_vo_compare.py; docs/dense_vo.md).
# Usage: bench/dense_vo_seeds.sh [BUILD_DIR] [OUT_DIR] [SEEDS]   (SEEDS: "1 2 3" by default)
set -euo pipefail
BUILD_DIR=${1:-build}
OUT=${2:-/tmp/pipescope_dense_vo}
SEEDS=${3:-1 2 3}
HERE=$(dirname "$0")
for seed in $SEEDS; do
  "$HERE/dense_vo_accuracy.sh" "$BUILD_DIR" "$OUT" "$seed"
done
# Signed errors, what each method adds to the floor no planar method observes (the robot's drift
# across the pipe and its tilt, bench/dense_vo_floor.py), and the paired comparison with the
# OpenCV baseline.
"$HERE/dense_vo_compare.py" "$OUT" "$SEEDS"
