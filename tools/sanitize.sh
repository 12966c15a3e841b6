#!/usr/bin/env bash
# The whole test suite under AddressSanitizer and UndefinedBehaviorSanitizer (GCC): builds
# build-asan/ (RelWithDebInfo, -DCCOMP_SANITIZE=ON) and runs ctest there. Any report fails:
# it aborts the process that made it (a test, or the ccomp command a test runs), and it is
# also logged under build-asan/sanitizer-reports/, which must stay empty (a test that
# expects the command to fail could otherwise pass over a report).
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/install-deps.sh
build=build-asan
nice -n 10 cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCCOMP_SANITIZE=ON \
  -DCCOMP_BUILD_BENCHMARKS=OFF >/dev/null
nice -n 10 cmake --build "$build" -j"$(nproc)"
bash tools/rs274/fetch.sh "$build/rs274"

reports="$PWD/$build/sanitizer-reports"
rm -rf "$reports"
mkdir -p "$reports"
export ASAN_OPTIONS="abort_on_error=1:detect_leaks=1:detect_stack_use_after_return=1:strict_string_checks=1:log_path=$reports/asan"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1:abort_on_error=1:log_path=$reports/ubsan"
# The whole suite: CI runs this after tools/test.sh on 2 cores within 90 minutes, and it
# fits (docs/robustness.md has the times).
status=0
nice -n 15 ctest --test-dir "$build" --output-on-failure -j"$(nproc)" || status=$?
if [ -n "$(ls -A "$reports")" ]; then
  cat "$reports"/*
  echo "sanitize.sh: sanitizer reports above (build-asan/sanitizer-reports/)" >&2
  exit 1
fi
exit "$status"
