#!/usr/bin/env bash
# The test suite built with AddressSanitizer and UndefinedBehaviorSanitizer (clang, which
# compiles it in about half gcc's time; -O1, line tables) in build-asan/, the two files that
# include ITK's headers by g++ with AddressSanitizer alone (ITK accepts no other compiler),
# run on the small synthetic phantoms: the tests on the real
# CT and the benchmark-sized runs are left to the Release suite (scripts/test.sh) to stay
# inside CI's time. Any sanitizer report fails the test that triggered it.
set -euo pipefail
cd "$(dirname "$0")/.."
build=${ASAN_BUILD_DIR:-build-asan}
# A folder that another compiler configured starts afresh: CMake would drop this script's
# options along with that cache.
if [ -f "$build/CMakeCache.txt" ] && ! grep -q '^CMAKE_CXX_COMPILER:.*clang++$' "$build/CMakeCache.txt"; then
  rm -rf "$build"
fi
cmake -S . -B "$build" -G Ninja -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=RelWithDebInfo -DMPUMESH_SANITIZE=ON -DMPUMESH_BUILD_BENCHMARKS=OFF \
  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1" -DCMAKE_C_FLAGS_RELWITHDEBINFO="-O1 -g1" >/dev/null
cmake --build "$build" -j "$(nproc)"
# Mesa's lavapipe and LLVM keep allocations until exit; the leak check covers our code.
# The sanitized build keeps the drivers mapped until exit (MPUMESH_KEEP_DRIVERS_LOADED in
# host/vk/context.cpp), so LeakSanitizer scans their globals and these names match.
supp=$(mktemp)
printf 'leak:libvulkan_lvp\nleak:libLLVM\nleak:libVkLayer_khronos_validation\nleak:libvulkan.so\nleak:libdbus\n' >"$supp"
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=1:strict_string_checks=1}
export LSAN_OPTIONS=suppressions=$supp
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
export MPUMESH_REQUIRE_VULKAN=${MPUMESH_REQUIRE_VULKAN:-1}
# The fit's accuracy runs on one shape (sphere slices) here; the other five take 3 of
# the sanitized suite's 4 minutes and run in the Release suite, as do the accuracy runs on
# the CT-like phantoms (Truth.*) and the runs on the sample CT and its masks. This build
# reads volumes in-process (core/CMakeLists.txt: its allocator is not fork-safe), so the tests
# of the readers' isolation from crashes and hangs run in the Release suite only. So do
# the four slowest runs here (45-90 s each under the sanitizers) whose code the smaller
# sanitized tests run too: the HTML report's spacing figures, the phantom's half level,
# the run's volume mesh report, and the larger of the two-label complexes.
skip='IsolatedRead.ErrorsCrashes|ReadersCrashOrHang|PydicomsCorpus|SampleCt|SampleProject|OnTheSampleCt|RunLargestOne|SampleCtIsTheSame|Browser|RunRemeshes|InterruptedRun|ThinPlate|Ellipsoid|FitsTheTrueSurface/(torus|ellipsoid|sphere_dense)|^Truth\.|ReportReadsTheRunReportsSpacingFigures|ScanPutsTheHalfLevelOnTheSurface|RunWritesTheVolumeMeshAndReportsIt|OneComplexWhoseTouchingLabelsShareTheirInterfaces'
ctest --test-dir "$build" -j "$(nproc)" --output-on-failure --timeout 1800 -E "$skip"
