#!/usr/bin/env bash
# Builds one libFuzzer target (fuzz/) with clang, ASan and UBSan in build-fuzz/ and runs it
# on seeds assembled from the repository's own inputs.
#   tools/fuzz.sh gcode|job|model|measurements|instruments|tool_table SECONDS|-runs=N [libFuzzer flags...]
# (job: the main job end to end on programs, the sample HMC's model; the others: one reader)
# New inputs that reach new code are kept in build-fuzz/corpus/<target>/ (reused by the next
# run); a crash, a sanitizer report, an exception other than ccomp::Error or an input that
# runs over 10 s (the job: 60 s) is written to build-fuzz/findings/<target>/ and stops the
# run (exit != 0).
# Replay one: build-fuzz/fuzz/ccomp_fuzz_<target> build-fuzz/findings/<target>/crash-...
set -euo pipefail
cd "$(dirname "$0")/.."
usage="usage: tools/fuzz.sh gcode|job|model|measurements|instruments|tool_table SECONDS|-runs=N [libFuzzer flags...]"
target=${1:?$usage}
budget=${2:?$usage}
shift 2
case "$budget" in
  -runs=*) limit=("$budget") ;;
  *[!0-9]* | "") echo "$usage" >&2; exit 2 ;;
  *) limit=("-max_total_time=$budget") ;;
esac

bash tools/install-deps.sh --fuzz
build=build-fuzz
seeds="$build/seeds/$target"
rm -rf "$seeds"
mkdir -p "$seeds" "$build/corpus/$target" "$build/findings/$target"
# Seeds: copies with names unique across folders; the large files give their head (the
# fuzzer reads no more than -max_len bytes of an input anyway).
seed() {
  local n=0 f
  while IFS= read -r -d '' f; do
    head -c 65536 "$f" >"$seeds/$n-$(basename "$f")"
    n=$((n + 1))
  done < <(find "$@" -type f -print0 | sort -z)
}
case "$target" in
  gcode | job)
    # Programs are short lines; 4 kB holds most of the corpus' programs whole.
    # fuzz/seeds/programs: the shapes of issue 49 (arcs of huge radius, G93 feeds, skipped
    # blocks in loops, arcs with P to flatten, full circles, blank lines, a changed header, TCP on and off).
    max_len=4096
    seed tests/data/corpus samples/programs samples/test-piece fuzz/seeds/programs -name '*.ngc' ;;
  model)
    max_len=8192
    seed samples/machines samples/measurements samples/test-piece -name '*.yaml' ;;
  measurements)
    max_len=4096
    # fuzz/seeds/measurements: short strokes, single runs, few targets, one direction, one row.
    seed samples/measurements samples/test-piece fuzz/seeds/measurements -name '*.csv' ;;
  instruments)
    # The samples of each instrument format, each behind a byte that picks its reader (and
    # the axis and unit options: fuzz/instruments_fuzz.cpp).
    max_len=4096
    n=0
    for f in samples/measurements/*.rtl samples/measurements/*.txt samples/measurements/x-axis-table.csv; do
      for pick in 01 09 00 08 02 04; do
        { printf "\\x$pick"; head -c 65535 "$f"; } >"$seeds/$n-$pick-$(basename "$f")"
        n=$((n + 1))
      done
    done ;;
  tool_table)
    max_len=1024
    seed samples tests/data -name '*.tbl' ;;
  *) echo "$usage" >&2; exit 2 ;;
esac
[ -n "$(ls -A "$seeds")" ] || { echo "fuzz.sh: no seeds for $target" >&2; exit 1; }

if [ ! -f "$build/build.ninja" ]; then
  CXX=clang++ nice -n 10 cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O2 -g" -DCCOMP_FUZZ=ON \
    -DCCOMP_BUILD_TESTS=OFF -DCCOMP_BUILD_BENCHMARKS=OFF >/dev/null
fi
nice -n 10 cmake --build "$build" --target "ccomp_fuzz_$target"

dict=()
dictionary=fuzz/$target.dict
[ "$target" = job ] && dictionary=fuzz/gcode.dict  # the job reads programs too
[ -f "$dictionary" ] && dict=("-dict=$dictionary")
# One process on purpose (no -jobs/-workers): the machines are shared. -timeout turns a
# hang into a finding; a report of either sanitizer aborts the run.
# No allocation stacks and a small quarantine: yaml-cpp allocates for every character it
# reads, and recording each allocation's stack cost the model target two thirds of its speed
# (250 against 770 executions a second). A finding replays with full reports:
# build-fuzz/fuzz/ccomp_fuzz_<target> FILE.
export ASAN_OPTIONS=${ASAN_OPTIONS:-abort_on_error=1:detect_leaks=1:malloc_context_size=0:quarantine_size_mb=16}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
# The job runs some 100x slower instrumented than built for speed: 60 s there is 0.5 s
# natively (a 4 kB program turning the table 1,400 degrees at 1 um writes 1,900 lines in
# 0.17 s, 20 s instrumented).
timeout=10
[ "$target" = job ] && timeout=60
exec nice -n 15 "$build/fuzz/ccomp_fuzz_$target" "${limit[@]}" -max_len="$max_len" -timeout="$timeout" \
  -artifact_prefix="$build/findings/$target/" -print_final_stats=1 "${dict[@]}" "$@" \
  "$build/corpus/$target" "$seeds"
