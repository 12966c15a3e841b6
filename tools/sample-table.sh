#!/usr/bin/env bash
# The before/after table of docs/compensation.md: every sample program with every sample
# machine: the error the machine makes on the program as written (ccomp predict) and what
# is left on ccomp's output (ccomp verify), at the default 1 um.
set -euo pipefail
cd "$(dirname "$0")/.."
ccomp=${CCOMP:-build/src/ccomp}
out=build/samples-out
echo "| machine | program | error before (max / rms) | left after (max / rms) | lines added |"
echo "|---|---|---:|---:|---:|"
for model in samples/machines/*.yaml; do
  name=$(basename "$model" .yaml)
  [ "$name" = zero ] && continue
  extra=()
  grep -q '^sensors:' "$model" && extra=(--sensor bed=24 --sensor column=23 --sensor spindle=31 --time 3600)
  for program in samples/programs/*.ngc samples/programs/*.mpf; do
    p=$(basename "$program")
    [ -f "$out/$name/$p" ] || continue
    dialect=()
    [ "${p##*.}" = mpf ] && dialect=(--dialect siemens)
    before=$("$ccomp" predict "$program" -m "$model" --tool-table samples/tools.tbl "${dialect[@]}" "${extra[@]}")
    # verify exits 7 when the output is off by more than the tolerance: the row says by how much.
    after=$("$ccomp" verify "$program" "$out/$name/$p" -m "$model" --tool-table samples/tools.tbl "${dialect[@]}" \
      "${extra[@]}" 2>/dev/null) || true
    # (the tip's figures: the tool direction's follow them on the line)
    pick() { sed -E 's/.*max ([0-9.]+) um.*rms ([0-9.]+) um;.*/\1 \/ \2 um/' <<< "$1"; }
    added=$(( $(wc -l < "$out/$name/$p") - $(wc -l < "$program") - 1 ))
    echo "| $name | $p | $(pick "$before") | $(pick "$after") | $added |"
  done
done
