#!/usr/bin/env bash
# Peak memory (max RSS, /usr/bin/time -v) of `ccomp check` on large measurement files: the
# sample HMC's nine laser lines simulated from its truth every STEP mm (default 1) with RUNS
# out-and-back runs (default "1 2 4": about 35k, 70k and 140k readings), checked against the
# geometric model (the README's walkthrough: refit, noise floor, the diagnosis of every
# candidate). Prints the readings, the peak and the memory each further reading takes (the
# slope between the sizes), which is what bounds the largest file a machine can check.
#   bench/check-memory.sh    (after tools/build.sh)
source "$(dirname "$0")/common.sh"
step=${STEP:-1}
truth=samples/measurements/hmc-truth.yaml
model=samples/machines/hmc-xyzb-geometric.yaml

peak_kb() {  # max RSS of one run, in kB
  /usr/bin/time -v -o "$work/time-v" "$ccomp" "$@" > /dev/null 2> "$work/err" || { cat "$work/err" >&2; exit 1; }
  if grep -q 'terminated by signal' "$work/time-v"; then head -1 "$work/time-v" >&2; exit 1; fi
  awk -F': ' '/Maximum resident set size/ {print $2}' "$work/time-v"
}

echo "ccomp check, peak memory (max RSS), nine lines every $step mm against $(basename "$model"):"
printf '  %10s %10s %10s %16s\n' readings "MB" "seconds" "kB per reading"
last_rows=0 last_kb=0
for runs in ${RUNS:-1 2 4}; do
  f="$work/nine-lines-$step-$runs.csv"
  [ -f "$f" ] || "$ccomp" simulate -m "$truth" --plan nine_lines --step "$step" --runs "$runs" -o "$f" > /dev/null 2> "$work/err" ||
    { cat "$work/err" >&2; exit 1; }
  rows=$(($(grep -vc '^#' "$f") - 1))
  start=$(date +%s%N)
  kb=$(peak_kb check "$f" -m "$model")
  ms=$((($(date +%s%N) - start) / 1000000))
  awk -v rows="$rows" -v kb="$kb" -v ms="$ms" -v lr="$last_rows" -v lk="$last_kb" 'BEGIN {
    slope = lr > 0 ? sprintf("%.2f", (kb - lk) / (rows - lr)) : "-"
    printf "  %10d %10.1f %10.1f %16s\n", rows, kb / 1024, ms / 1000, slope }'
  last_rows=$rows last_kb=$kb
done
