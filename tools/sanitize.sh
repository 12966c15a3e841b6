#!/usr/bin/env bash
# The whole test suite under AddressSanitizer and UndefinedBehaviorSanitizer (GCC), what
# tools/test.sh runs: builds build-asan/ (-O2 with line tables only, -DCCOMP_SANITIZE=ON; full
# debug information made the build half as long again; the benchmarks are left to
# tools/setup.sh's Release build) and runs ctest there. Any report fails:
# it aborts the process that made it (a test, or the ccomp command a test runs), and it is
# also logged under build-asan/sanitizer-reports/, which must stay empty (a test that
# expects the command to fail could otherwise pass over a report).
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/install-deps.sh
build=build-asan
nice -n 10 cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O2 -g1 -DNDEBUG" -DCCOMP_SANITIZE=ON -DCCOMP_BUILD_BENCHMARKS=OFF >/dev/null
nice -n 10 cmake --build "$build" -j"$(nproc)"
bash tools/rs274/fetch.sh "$build/rs274"

reports="$PWD/$build/sanitizer-reports"
rm -rf "$reports"
mkdir -p "$reports"
export ASAN_OPTIONS="abort_on_error=1:detect_leaks=1:detect_stack_use_after_return=1:strict_string_checks=1:log_path=$reports/asan"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1:abort_on_error=1:log_path=$reports/ubsan"
# The whole suite (docs/robustness.md has the times on CI's 2 cores).
status=0
nice -n 15 ctest --test-dir "$build" --output-on-failure -j"$(nproc)" || status=$?
if [ -n "$(ls -A "$reports")" ]; then
  cat "$reports"/*
  echo "sanitize.sh: sanitizer reports above (build-asan/sanitizer-reports/)" >&2
  exit 1
fi
exit "$status"
