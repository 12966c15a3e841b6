#!/usr/bin/env bash
# The front end's speed, end to end: `ccomp in.ngc -m zero.yaml -o out.ngc` (parse,
# interpret, write) against LinuxCNC's `rs274 -g` on the same files, plus tokenising in
# memory and peak memory on a 10M-line program. Prints the figures the README quotes.
#   bench/frontend.sh            (after tools/build.sh and tools/rs274/fetch.sh build/rs274)
source "$(dirname "$0")/common.sh"
repeats=${REPEATS:-5}

[ -f "$work/finishing-1M.ngc" ] || "$build/bench/ccomp_bench_generate" 1000000 "$work/finishing-1M.ngc"
printf 'T1 P1 Z0.5 D0.25\n' > "$work/tools.tbl"  # rs274 alone reads inches

median() { sort -g | awk '{a[NR]=$1} END {print a[int((NR+1)/2)]}'; }
seconds() {  # median wall time of a command over $repeats runs
  for _ in $(seq "$repeats"); do
    local t0 t1
    t0=$(date +%s.%N); "$@" >/dev/null 2>&1; t1=$(date +%s.%N)
    echo "$t1 - $t0" | bc -l
  done | median
}

printf '%-22s %10s %10s %12s %10s %12s %8s\n' program lines MB "ccomp s" "MB/s" "lines/s" ""
for program in tests/data/corpus/programs/stellabee1.ngc "$work/finishing-1M.ngc"; do
  lines=$(wc -l < "$program")
  bytes=$(stat -c %s "$program")
  ours=$(seconds "$ccomp" "$program" -m samples/machines/zero.yaml -o "$work/out.ngc" --tool-table "$work/tools.tbl" --machine-units inch)
  name=$(basename "$program")
  printf '%-22s %10d %10.1f %12.3f %10.1f %12.0f   ccomp\n' "$name" "$lines" "$(echo "$bytes/1000000" | bc -l)" \
    "$ours" "$(echo "$bytes/1000000/$ours" | bc -l)" "$(echo "$lines/$ours" | bc -l)"
  if [ -x "$rs274" ]; then
    theirs=$(REPEATS=$(( repeats < 3 ? repeats : 3 )) seconds "$rs274" -t "$work/tools.tbl" -g "$program")
    printf '%-22s %10d %10.1f %12.3f %10.1f %12.0f   rs274 -g\n' "$name" "$lines" "$(echo "$bytes/1000000" | bc -l)" \
      "$theirs" "$(echo "$bytes/1000000/$theirs" | bc -l)" "$(echo "$lines/$theirs" | bc -l)"
    printf '%-22s ccomp is %.1fx rs274\n' "$name" "$(echo "$theirs/$ours" | bc -l)"
  else
    echo "(rs274 not found at $rs274: run tools/rs274/fetch.sh $build/rs274 for the ratio)"
  fi
done

echo
echo "tokenising and parse+interpret in memory (stellabee1.ngc):"
"$build/bench/ccomp_bench_frontend" --benchmark_repetitions=3 --benchmark_report_aggregates_only=true \
  --benchmark_filter='.*' 2>/dev/null | grep -E '_median|Benchmark'

echo
echo "peak memory (max RSS) of the main job as the program grows:"
for n in 1000000 10000000; do
  f=$(generated_program "$n")
  rss=$(/usr/bin/time -f '%M' "$ccomp" "$f" -m samples/machines/zero.yaml -o "$work/out.ngc" \
        --tool-table "$work/tools.tbl" --machine-units inch 2>&1 >/dev/null | tail -1)
  printf '  %9d lines (%5.0f MB): %6.1f MB\n' "$n" "$(echo "$(stat -c %s "$f")/1000000" | bc -l)" "$(echo "$rss/1024" | bc -l)"
done
rm -f "$work/out.ngc"
