#!/usr/bin/env bash
# Runs every Google Benchmark kernel and prints its table; results worth keeping are copied into
# docs/benchmarks.md by hand with the date and machine.
set -euo pipefail
build_dir="${1:-build}"
for bench in "$build_dir"/bench/*_bench; do
  echo "== $(basename "$bench")"
  "$bench" --benchmark_min_time=0.2
done
