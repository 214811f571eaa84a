#!/bin/bash
# Runs each parser fuzzer (fuzz/, docs/fuzzing.md) for SECONDS_PER_TARGET seconds, one after the
# other, on a fresh copy of its seed corpus (fuzz/corpus/TARGET), and prints per target the
# inputs executed and whether it found a crash, timeout or memory blow-up. Configures and builds
# BUILD_DIR with clang and the sanitizers first if needed. Exits 1 when any target failed.
# Logs, grown corpora and failing inputs (crash-*, timeout-*, oom-*, leak-*) are kept under
# BUILD_DIR/fuzz-runs/TARGET/.
# Usage: bench/fuzz.sh [SECONDS_PER_TARGET] [BUILD_DIR]
#        FUZZ_TARGETS="camera_yaml_fuzzer ..." bench/fuzz.sh ...   (a subset)
set -euo pipefail
SECONDS_PER_TARGET=${1:-600}
ROOT=$(cd "$(dirname "$0")/.." && pwd)
BUILD_DIR=${2:-$ROOT/build-fuzz}
TARGETS=${FUZZ_TARGETS:-"manifest_fuzzer camera_yaml_fuzzer tum_fuzzer junctions_fuzzer
         scene_yaml_fuzzer config_fuzzer"}

# Gently: the machine may be shared, so one core at low priority.
if [ ! -f "$BUILD_DIR/build.ninja" ]; then
  CC=clang CXX=clang++ cmake -S "$ROOT" -B "$BUILD_DIR" -G Ninja \
    -DCMAKE_BUILD_TYPE=RelWithDebInfo -DPIPESCOPE_FUZZ=ON \
    -DPIPESCOPE_BUILD_TESTS=OFF -DPIPESCOPE_BUILD_BENCH=OFF
fi
nice -n 15 cmake --build "$BUILD_DIR" -j1 --target fuzzers

export UBSAN_OPTIONS=print_stacktrace=1
results=""
failed=0
for target in $TARGETS; do
  name=${target%_fuzzer}
  run="$BUILD_DIR/fuzz-runs/$target"
  rm -rf "$run"
  mkdir -p "$run/artifacts" "$run/tmp"
  cp -r "$ROOT/fuzz/corpus/$name" "$run/corpus"
  echo "== $target: ${SECONDS_PER_TARGET} s" >&2
  status=0
  # The targets write their inputs under TMPDIR; keep those files with the run.
  TMPDIR="$run/tmp" nice -n 15 "$BUILD_DIR/fuzz/$target" "$run/corpus" -max_total_time="$SECONDS_PER_TARGET" \
    -rss_limit_mb=2048 -timeout=10 -print_final_stats=1 -artifact_prefix="$run/artifacts/" \
    >"$run/log.txt" 2>&1 || status=$?
  executions=$(sed -n 's/^stat::number_of_executed_units: *//p' "$run/log.txt" | tail -1)
  artifacts=$(cd "$run/artifacts" && ls)
  if [ "$status" -ne 0 ] || [ -n "$artifacts" ]; then
    failed=1
    outcome="FAILED (exit $status): $(echo "$artifacts" | tr '\n' ' ')see $run/log.txt"
  else
    outcome="no crash"
  fi
  results+=$(printf "%-20s %8s %12s  %s" "$target" "$SECONDS_PER_TARGET" "${executions:-?}" \
    "$outcome")$'\n'
done
printf "%-20s %8s %12s  %s\n" target seconds executions outcome
printf "%s" "$results"
exit "$failed"
