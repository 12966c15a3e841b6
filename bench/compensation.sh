#!/usr/bin/env bash
# The main job's speed with a real model: the 1M-line finishing program compensated with
# the full 46-term HMC at 1 um, against LinuxCNC's rs274 -g reading the same file; the
# inverse's points/s; and how many lines compensation adds per move as the tolerance
# tightens (the table in docs/compensation.md).
#   bench/compensation.sh    (after tools/build.sh and tools/rs274/fetch.sh build/rs274)
source "$(dirname "$0")/common.sh"
model=samples/machines/hmc-xyzb.yaml
sensors=(--sensor bed=24 --sensor column=23 --sensor spindle=31 --time 3600)
[ -f "$work/finishing-1000000.ngc" ] || "$build/bench/ccomp_bench_generate" 1000000 "$work/finishing-1000000.ngc"
program="$work/finishing-1000000.ngc"
printf 'T1 P1 Z3.937 D0.25\n' > "$work/tools-inch.tbl"   # rs274 alone reads inches: 100 mm
printf 'T1 P1 Z100 D6\n' > "$work/tools-mm.tbl"
lines=$(wc -l < "$program")

steal0=$(awk '/^cpu /{print $9}' /proc/stat)
echo "main job, $model at 1 um, $(basename "$program") ($lines lines):"
for threads in 2 1; do
  t0=$(date +%s.%N)
  /usr/bin/time -f '%M %U' -o "$work/rss" "$ccomp" "$program" -m "$model" -o "$work/out.ngc" \
    --tool-table "$work/tools-mm.tbl" "${sensors[@]}" --threads "$threads" 2> "$work/summary" ||
    { cat "$work/summary"; exit 1; }
  t1=$(date +%s.%N)
  seconds=$(echo "$t1 - $t0" | bc -l)
  [ "$threads" = 2 ] && ours=$seconds
  read -r rss user < "$work/rss"
  printf '  ccomp, %d thread(s) %7.2f s  %9.0f lines/s  (CPU %.2f s)  peak RSS %.1f MB\n' "$threads" "$seconds" \
    "$(echo "$lines/$seconds" | bc -l)" "$user" "$(echo "$rss/1024" | bc -l)"
done
sed 's/^/  /' "$work/summary"
if [ -x "$rs274" ]; then
  t0=$(date +%s.%N)
  /usr/bin/time -f '%U' -o "$work/cpu" "$rs274" -t "$work/tools-inch.tbl" -g "$program" > /dev/null 2>&1
  t1=$(date +%s.%N)
  theirs=$(echo "$t1 - $t0" | bc -l)
  printf '  rs274 -g            %7.2f s  %9.0f lines/s  (CPU %.2f s)\n' "$theirs" "$(echo "$lines/$theirs" | bc -l)" \
    "$(tail -1 "$work/cpu")"
  printf '  ccomp compensating (2 threads) is %.1fx rs274 reading\n' "$(echo "$theirs/$ours" | bc -l)"
fi
# On a shared machine the hypervisor may take part of the CPU time: the wall times above
# then mean less than usual.
steal1=$(awk '/^cpu /{print $9}' /proc/stat)
printf '  CPU time taken by the hypervisor meanwhile (steal): %.1f s\n' \
  "$(echo "($steal1 - $steal0) / $(getconf CLK_TCK)" | bc -l)"

echo
echo "inverse and forward model (Google Benchmark):"
"$build/bench/ccomp_bench_compensation" --benchmark_repetitions=3 --benchmark_report_aggregates_only=true 2>/dev/null |
  grep -E 'median|Benchmark'

echo
echo "lines added per move against tolerance (samples/programs/pocket-xy.ngc, $model):"
printf '  %-10s %8s %12s %14s\n' tolerance moves "lines added" "per move"
for tol in 0.010 0.005 0.002 0.001 0.0005 0.0002; do
  "$ccomp" samples/programs/pocket-xy.ngc -m "$model" -o "$work/t.ngc" --tool-table samples/tools.tbl \
    "${sensors[@]}" --tolerance "$tol" 2> "$work/t.txt"
  # the summary line only: at fine tolerances the digits' warning comes first
  summary=$(grep 'moves compensated' "$work/t.txt")
  moves=$(sed -E 's/.*: ([0-9]+) moves compensated \(([0-9]+) lines added\).*/\1/' <<< "$summary")
  added=$(sed -E 's/.*: ([0-9]+) moves compensated \(([0-9]+) lines added\).*/\2/' <<< "$summary")
  printf '  %-10s %8d %12d %14.1f\n' "$(echo "$tol*1000" | bc -l | sed 's/0*$//;s/\.$//') um" "$moves" "$added" \
    "$(echo "$added/$moves" | bc -l)"
done

echo
echo "peak memory with bent moves (full circles of 100 mm radius, about 1,000 chords each at 1 um):"
for circles in 400 1600; do
  { printf 'G21 G90 G94 G54\nT1 M6\nG43 H1\nG0 X100 Y0 Z-90 B0\nG1 F1500\n'
    for ((k = 0; k < circles; ++k)); do printf 'G2 X100 Y0 I-100 J0\n'; done
    printf 'M30\n'; } > "$work/circles.ngc"
  t0=$(date +%s.%N)
  /usr/bin/time -f '%M' -o "$work/rss" "$ccomp" "$work/circles.ngc" -m "$model" -o "$work/out.ngc" \
    --tool-table "$work/tools-mm.tbl" "${sensors[@]}" 2> "$work/summary" || { cat "$work/summary"; exit 1; }
  t1=$(date +%s.%N)
  printf '  %5d circles: %9d lines written in %6.2f s, peak RSS %.1f MB\n' "$circles" "$(wc -l < "$work/out.ngc")" \
    "$(echo "$t1 - $t0" | bc -l)" "$(echo "$(cat "$work/rss")/1024" | bc -l)"
done
rm -f "$work/out.ngc" "$work/t.ngc" "$work/circles.ngc"
