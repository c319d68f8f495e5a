#!/usr/bin/env bash
# Builds the libFuzzer targets (tests/fuzz, clang with ASan + UBSan) in build-fuzz/ and
# runs each for FUZZ_SECONDS (default 30) from its checked-in seed corpus (the volume
# target's DICOM seeds from python3-pydicom); the regression
# inputs in tests/fuzz/regressions/ are replayed first. Exits non-zero on any finding; the
# input that caused it is left in build-fuzz/artifacts/.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${FUZZ_SECONDS:-30}
build=${FUZZ_BUILD_DIR:-build-fuzz}
CC=clang CXX=clang++ cmake -S . -B "$build" -G Ninja -DMPUMESH_FUZZ_ONLY=ON -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
cmake --build "$build" -j "$(nproc)"
mkdir -p "$build/artifacts"
# The volume target's DICOM seeds: pydicom's test files (python3-pydicom), each behind the
# byte that picks .dcm (4). Its reads run in a child whose time limit is short here.
pydicom=/usr/lib/python3/dist-packages/pydicom/data/test_files
mkdir -p "$build/corpus/volume"
if [ -d "$pydicom" ]; then
  for f in "$pydicom"/*.dcm; do
    if [ "$(stat -c %s "$f")" -le 65535 ]; then
      { printf '\x04'; cat "$f"; } > "$build/corpus/volume/dicom-$(basename "$f")"
    fi
  done
fi
export MPUMESH_READER_TIMEOUT=${MPUMESH_READER_TIMEOUT:-5}
# One target: its regression inputs replayed, then FUZZ_SECONDS of fuzzing.
fuzz_one() {
  local t=$1 work="$build/corpus/$1"
  mkdir -p "$work"
  if [ -d "tests/fuzz/regressions/$t" ]; then
    "$build/tests/fuzz/fuzz_$t" -runs=0 tests/fuzz/regressions/$t/* 2>&1 | tail -1
  fi
  echo "fuzz_$t: ${seconds}s from tests/fuzz/corpus/$t"
  # The volume target's third-party readers run in a child process, where a large
  # allocation is theirs to make or to fail (their failure comes back as an error): the
  # malloc limit is the parent's memory, and a refused allocation returns null.
  local extra=() asan=${ASAN_OPTIONS:-}
  if [ "$t" = volume ]; then
    extra=(-malloc_limit_mb=65536)
    asan="allocator_may_return_null=1${asan:+:$asan}"
  fi
  ASAN_OPTIONS=$asan "$build/tests/fuzz/fuzz_$t" "$work" "tests/fuzz/corpus/$t" -max_total_time="$seconds" -rss_limit_mb=2048 \
    -timeout=10 -max_len=65536 -artifact_prefix="$build/artifacts/${t}-" -print_final_stats=1 "${extra[@]}" 2>&1 |
    grep -E "^(stat::number_of_executed_units|stat::peak_rss_mb|Done|==[0-9]+==ERROR|SUMMARY)|runtime error" || true
}
# The targets run as many at a time as there are cores (each fuzzes on one); a target
# whose replay or run fails, or that leaves an input behind, is a finding.
targets=(mpu mesh points plist inv3 dicom volume tet)
declare -A pid
for t in "${targets[@]}"; do
  fuzz_one "$t" >"$build/fuzz_$t.log" 2>&1 &
  pid[$t]=$!
  while [ "$(jobs -rp | wc -l)" -ge "$(nproc)" ]; do wait -n || true; done
done
found=0
for t in "${targets[@]}"; do
  status=0
  wait "${pid[$t]}" || status=$?
  cat "$build/fuzz_$t.log"
  if ls "$build/artifacts/${t}-"* >/dev/null 2>&1; then
    echo "fuzz_$t: FOUND a failing input: $(ls "$build/artifacts/${t}-"*)" >&2
    found=1
  elif [ "$status" -ne 0 ]; then
    echo "fuzz_$t: FAILED (exit $status)" >&2
    found=1
  fi
done
[ "$found" -eq 0 ] || exit 1
echo "fuzz: no findings"
