#!/usr/bin/env bash
# The differential fuzzer against LinuxCNC's rs274: COUNT generated programs (default
# 10,000) of BLOCKS blocks each (default 120), split over the cores; ccomp's motions must
# equal rs274's. Each program that diverges is cut down to the smallest that still does and
# written, with what differs, to build/rs274-diff/part-*/seed-N.{ngc,txt}. Exit 1 when any
# diverges. Run after tools/build.sh (it fetches rs274 as tools/test.sh does).
#   bash tools/rs274-diff.sh [COUNT [BLOCKS [FIRST_SEED]]]
set -euo pipefail
cd "$(dirname "$0")/.."
count=${1:-10000}
blocks=${2:-120}
first=${3:-1}
bash tools/rs274/fetch.sh build/rs274
cmake --build build --target ccomp_rs274_diff >/dev/null
out=build/rs274-diff
rm -rf "$out" "$out"-part-*.log
jobs=$(nproc)
per=$(((count + jobs - 1) / jobs))
pids=()
for ((j = 0; j < jobs; ++j)); do
  start=$((first + j * per))
  n=$((count - j * per < per ? count - j * per : per))
  ((n > 0)) || continue
  build/tests/ccomp_rs274_diff "$start" "$n" "$blocks" "$out/part-$j" > "$out-part-$j.log" 2>&1 &
  pids+=($!)
done
status=0
for pid in "${pids[@]}"; do wait "$pid" || status=1; done
cat "$out"-part-*.log
exit "$status"
