#!/usr/bin/env bash
# Peak memory (max RSS, /usr/bin/time -v) of the main job on the generated 3-axis finishing
# program (bench/generate_program.cpp) of 1M and 10M lines: with the zero model (parse,
# interpret, write: the front end alone) and with the full 46-term HMC model at 1 um (the
# compensation's own state and the second thread's queues; 1M lines is the program
# bench/compensation.sh times), and `verify` of the full model's output. Prints the figures
# the README quotes.
#   bench/memory.sh    (after tools/build.sh)
source "$(dirname "$0")/common.sh"
sizes=${SIZES:-1000000 10000000}
printf 'T1 P1 Z0.5 D0.25\n' > "$work/tools-inch.tbl"  # the zero model's runs, as bench/frontend.sh
printf 'T1 P1 Z100 D6\n' > "$work/tools-mm.tbl"       # the HMC's, as bench/compensation.sh
full=(-m samples/machines/hmc-xyzb.yaml --tool-table "$work/tools-mm.tbl"
      --sensor bed=24 --sensor column=23 --sensor spindle=31 --time 3600)
zero=(-m samples/machines/zero.yaml --tool-table "$work/tools-inch.tbl" --machine-units inch)

peak_mb() {  # max RSS of one run, in MB (1 MB = 1024 kB as time -v counts)
  /usr/bin/time -v -o "$work/time-v" "$ccomp" "$@" > /dev/null 2> "$work/err" || { cat "$work/err" >&2; exit 1; }
  awk -F': ' '/Maximum resident set size/ {printf "%.1f", $2 / 1024}' "$work/time-v"
}

echo "peak memory (max RSS):"
printf '  %-10s %9s %14s %14s %14s\n' lines "MB in" "zero model" "full HMC model" "verify"
for n in $sizes; do
  f=$(generated_program "$n")
  zero_mb=$(peak_mb "$f" "${zero[@]}" -o "$work/out.ngc" -q)
  full_mb=$(peak_mb "$f" "${full[@]}" -o "$work/out.ngc" -q)
  verify_mb=$(peak_mb verify "$f" "$work/out.ngc" "${full[@]}")
  printf '  %-10d %9.0f %11s MB %11s MB %11s MB\n' "$n" "$(echo "$(stat -c %s "$f")/1000000" | bc -l)" "$zero_mb" \
    "$full_mb" "$verify_mb"
done
rm -f "$work/out.ngc"
