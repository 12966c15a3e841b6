#!/usr/bin/env bash
# The main job's speed with a real model: the 1M-line finishing program compensated with
# the full 46-term HMC at 1 um on two threads and one, the zero model's main job, verify
# and predict, against LinuxCNC's rs274 -g reading the same file (median of ROUNDS interleaved
# runs, 5 by default), with the speed targets met or not; the inverse's points/s; and how
# many lines compensation adds per move as the tolerance tightens (docs/compensation.md);
# the peak memory with bent moves; the five-axis samples' main job and verify.
#   bench/compensation.sh    (after tools/build.sh and tools/rs274/fetch.sh build/rs274)
source "$(dirname "$0")/common.sh"
model=samples/machines/hmc-xyzb.yaml
sensors=(--sensor bed=24 --sensor column=23 --sensor spindle=31 --time 3600)
program=$(generated_program 1000000)
printf 'T1 P1 Z3.937 D0.25\n' > "$work/tools-inch.tbl"   # rs274 alone reads inches: 100 mm
printf 'T1 P1 Z100 D6\n' > "$work/tools-mm.tbl"
lines=$(wc -l < "$program")
rounds=${ROUNDS:-5}
load=$(cut -d' ' -f1-3 /proc/loadavg)

steal0=$(awk '/^cpu /{print $9}' /proc/stat)
echo "main job, $model at 1 um, $(basename "$program") ($lines lines), median of $rounds interleaved runs:"
# One round runs each command once, in turn, so that a slow spell of the shared machine
# falls on all of them alike; the medians are compared.
run() {  # run NAME COMMAND...: appends the wall seconds to $work/times-NAME, the peak RSS (KB) to rss-NAME
  local name=$1
  shift
  local t0 t1
  t0=$(date +%s.%N)
  /usr/bin/time -f '%M' -o "$work/rss-last" "$@" > /dev/null 2> "$work/err-$name" || { cat "$work/err-$name"; exit 1; }
  t1=$(date +%s.%N)
  echo "$t1 - $t0" | bc -l >> "$work/times-$name"
  cat "$work/rss-last" >> "$work/rss-$name"
}
median() { sort -g "$work/times-$1" | awk '{v[NR] = $1} END {print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2}'; }
peak() { sort -g "$work/rss-$1" | tail -1; }
# The fastest and slowest runs: on these shared machines a two-thread run can fall in a spell
# where the same work takes half as much CPU time again, and a median can land in one.
spread() { sort -g "$work/times-$1" | awk 'NR == 1 {lo = $1} {hi = $1} END {printf "%.2f-%.2f s", lo, hi}'; }
rm -f "$work"/times-* "$work"/rss-*
job=(--tool-table "$work/tools-mm.tbl" "${sensors[@]}" --force -q)
for ((round = 0; round < rounds; ++round)); do
  run two "$ccomp" "$program" -m "$model" -o "$work/out.ngc" "${job[@]}" --threads 2
  run one "$ccomp" "$program" -m "$model" -o "$work/out-1.ngc" "${job[@]}" --threads 1
  run zero "$ccomp" "$program" -m samples/machines/zero.yaml -o "$work/out-zero.ngc" \
    --tool-table "$work/tools-mm.tbl" --force -q --threads 2
  run verify "$ccomp" verify "$program" "$work/out.ngc" -m "$model" --tool-table "$work/tools-mm.tbl" "${sensors[@]}"
  run predict "$ccomp" predict "$program" -m "$model" --tool-table "$work/tools-mm.tbl" "${sensors[@]}"
  if [ -x "$rs274" ]; then run rs274 "$rs274" -t "$work/tools-inch.tbl" -g "$program"; fi
done
cmp -s "$work/out.ngc" "$work/out-1.ngc" || { echo "  the outputs of 1 and 2 threads differ" >&2; exit 1; }
for name in two one zero verify predict; do
  label=$(case $name in two) echo "ccomp, 2 threads";; one) echo "ccomp, 1 thread";; zero) echo "ccomp, zero model";;
          verify) echo "ccomp verify";; predict) echo "ccomp predict";; esac)
  m=$(median $name)
  printf '  %-18s %7.2f s  %9.0f lines/s  peak RSS %.1f MB  (runs %s)\n' "$label" "$m" "$(echo "$lines/$m" | bc -l)" \
    "$(echo "$(peak $name)/1024" | bc -l)" "$(spread $name)"
done
if [ -x "$rs274" ]; then
  theirs=$(median rs274)
  printf '  %-18s %7.2f s  %9.0f lines/s\n' "rs274 -g" "$theirs" "$(echo "$lines/$theirs" | bc -l)"
  # The targets of the issue on speed: 10x rs274 on two threads, 5x on one, within 3x of
  # the zero model; the same for verify.
  check() {  # check WHAT RATIO TARGET
    printf '  %-44s %6.1fx  (target %sx: %s)\n' "$1" "$2" "$3" "$(echo "$2 >= $3" | bc -l | sed 's/1/met/;s/0/not met/')"
  }
  check "ccomp 2 threads against rs274" "$(echo "$theirs/$(median two)" | bc -l)" 10
  check "ccomp 1 thread against rs274" "$(echo "$theirs/$(median one)" | bc -l)" 5
  check "verify against rs274" "$(echo "$theirs/$(median verify)" | bc -l)" 10
  printf '  %-44s %6.1fx  (no target of its own)\n' "predict against rs274" "$(echo "$theirs/$(median predict)" | bc -l)"
  printf '  %-44s %6.1fx  (target at most 3x: %s)\n' "ccomp 2 threads against the zero model" \
    "$(echo "$(median two)/$(median zero)" | bc -l)" \
    "$(echo "$(median two) <= 3 * $(median zero)" | bc -l | sed 's/1/met/;s/0/not met/')"
fi
# On a shared machine the hypervisor may take part of the CPU time: the wall times above
# then mean less than usual.
steal1=$(awk '/^cpu /{print $9}' /proc/stat)
printf '  CPU time taken by the hypervisor meanwhile (steal): %.1f s; load average before: %s\n' \
  "$(echo "($steal1 - $steal0) / $(getconf CLK_TCK)" | bc -l)" "$load"

echo
echo "inverse and forward model (Google Benchmark):"
"$build/bench/ccomp_bench_compensation" --benchmark_repetitions=3 --benchmark_report_aggregates_only=true 2>/dev/null |
  grep -E 'median|Benchmark'

echo
echo "lines added per move against tolerance (samples/programs/pocket-xy.ngc, $model):"
printf '  %-10s %8s %12s %14s\n' tolerance moves "lines added" "per move"
for tol in 0.010 0.005 0.002 0.001 0.0005 0.0002; do
  "$ccomp" samples/programs/pocket-xy.ngc -m "$model" -o "$work/t.ngc" --tool-table samples/tools.tbl \
    "${sensors[@]}" --tolerance "$tol" 2> "$work/t.txt" || [ $? -eq 1 ]  # 1: written, verdict failed
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
    --tool-table "$work/tools-mm.tbl" "${sensors[@]}" 2> "$work/summary" || [ $? -eq 1 ] || { cat "$work/summary"; exit 1; }
  t1=$(date +%s.%N)
  printf '  %5d circles: %9d lines written in %6.2f s, peak RSS %.1f MB\n' "$circles" "$(wc -l < "$work/out.ngc")" \
    "$(echo "$t1 - $t0" | bc -l)" "$(echo "$(cat "$work/rss")/1024" | bc -l)"
done

echo
# Five-axis: the TCP sample, whose verify follows the control's kinematics through the
# nominal chain at every point (MeantDirection in src/compensate/verify.cpp), and the
# joint-coordinate sample; one round is one run of each command, in turn. The main job's
# time includes its verdict (a verify of what it wrote).
five=samples/machines/vmc-xyzac-trunnion.yaml
echo "five-axis samples on $five, median of $rounds interleaved runs:"
rm -f "$work"/times-* "$work"/rss-*
for ((round = 0; round < rounds; ++round)); do
  for kind in tcp joint; do
    program5=samples/programs/five-axis-xyzac.ngc
    [ "$kind" = tcp ] && program5=samples/programs/five-axis-tcp-xyzac.ngc
    run "job-$kind" "$ccomp" "$program5" -m "$five" -o "$work/out5-$kind.ngc" --tool-table samples/tools.tbl --force -q
    run "verify-$kind" "$ccomp" verify "$program5" "$work/out5-$kind.ngc" -m "$five" --tool-table samples/tools.tbl
  done
done
for name in job-tcp verify-tcp job-joint verify-joint; do
  printf '  %-18s %7.3f s  (runs %s)\n' "$name" "$(median "$name")" \
    "$(sort -g "$work/times-$name" | awk 'NR == 1 {lo = $1} {hi = $1} END {printf "%.3f-%.3f s", lo, hi}')"
done
rm -f "$work/out.ngc" "$work/t.ngc" "$work/circles.ngc" "$work"/out5-*.ngc
