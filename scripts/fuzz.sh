#!/usr/bin/env bash
# Builds the libFuzzer targets (tests/fuzz, clang with ASan + UBSan) in build-fuzz/ and
# runs each for FUZZ_SECONDS (default 30) from its checked-in seed corpus; the regression
# inputs in tests/fuzz/regressions/ are replayed first. Exits non-zero on any finding; the
# input that caused it is left in build-fuzz/artifacts/.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${FUZZ_SECONDS:-30}
build=${FUZZ_BUILD_DIR:-build-fuzz}
CC=clang CXX=clang++ cmake -S . -B "$build" -G Ninja -DMPUMESH_FUZZ_ONLY=ON -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
cmake --build "$build" -j "$(nproc)"
mkdir -p "$build/artifacts"
for t in mpu mesh points plist inv3 dicom volume; do
  work="$build/corpus/$t"
  mkdir -p "$work"
  if [ -d "tests/fuzz/regressions/$t" ]; then
    "$build/tests/fuzz/fuzz_$t" -runs=0 tests/fuzz/regressions/$t/* 2>&1 | tail -1
  fi
  echo "fuzz_$t: ${seconds}s from tests/fuzz/corpus/$t"
  "$build/tests/fuzz/fuzz_$t" "$work" "tests/fuzz/corpus/$t" -max_total_time="$seconds" -rss_limit_mb=2048 \
    -timeout=10 -max_len=65536 -artifact_prefix="$build/artifacts/${t}-" -print_final_stats=1 2>&1 |
    grep -E "^(stat::number_of_executed_units|stat::peak_rss_mb|Done|==[0-9]+==ERROR|SUMMARY)|runtime error" || true
  if ls "$build/artifacts/${t}-"* >/dev/null 2>&1; then
    echo "fuzz_$t: FOUND a failing input: $(ls "$build/artifacts/${t}-"*)" >&2
    exit 1
  fi
done
echo "fuzz: no findings"
