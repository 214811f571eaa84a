#!/bin/bash
# The dense benchmark (bench/dense_vo_accuracy.sh) over several seeds: one seed's figures at
# hundredths of a per cent depend on the texture and on where key frames fall, so methods are
# ranked by the mean and the worst distance error over seeds (docs/dense_vo.md).
# Usage: bench/dense_vo_seeds.sh [BUILD_DIR] [OUT_DIR] [SEEDS]   (SEEDS: "1 2 3" by default)
set -euo pipefail
BUILD_DIR=${1:-build}
OUT=${2:-/tmp/pipescope_dense_vo}
SEEDS=${3:-1 2 3}
HERE=$(dirname "$0")
TABLE=$(mktemp)
trap 'rm -f "$TABLE"' EXIT
for seed in $SEEDS; do
  "$HERE/dense_vo_accuracy.sh" "$BUILD_DIR" "$OUT" "$seed" | tee -a "$TABLE"
done
# What no planar method observes, per dataset, from ground truth (bench/dense_vo_floor.py).
for seed in $SEEDS; do
  for preset in steel-6in steel-16in; do "$HERE/dense_vo_floor.py" "$OUT/$preset-seed$seed"; done
done
python3 - "$TABLE" <<'PY'
import collections, sys
errors = collections.defaultdict(list)
returns = collections.defaultdict(list)
for line in open(sys.argv[1]):
    cells = line.split()
    if len(cells) < 6 or cells[0] == "preset":
        continue
    errors[(cells[0], cells[1])].append(float(cells[2]))
    if cells[5] != "-":
        returns[(cells[0], cells[1])].append(float(cells[5]))
print(f"\n{'preset':<11} {'method':<15} {'seeds':>5} {'mean_err':>9} {'max_err':>9} "
      f"{'mean_ret':>9} {'max_ret':>9}")
for (preset, method), values in errors.items():
    ret = returns.get((preset, method), [])
    mean_ret = f"{sum(ret) / len(ret):.3f}" if ret else "-"
    max_ret = f"{max(ret):.3f}" if ret else "-"
    print(f"{preset:<11} {method:<15} {len(values):>5} {sum(values) / len(values):9.3f} "
          f"{max(values):9.3f} {mean_ret:>9} {max_ret:>9}")
PY
