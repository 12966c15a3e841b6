#!/usr/bin/env bash
# The metrology loop of the README on the shipped measurements: check the model against
# them, add the effect check names first, refit, and again until nothing is missing. It
# prints what the README quotes (tests/cli/walkthrough_test.cpp compares the two). Run
# after tools/build.sh. The measurements were simulated from a hidden truth
# (samples/measurements/README.md).
set -euo pipefail
cd "$(dirname "$0")/.."
ccomp=${CCOMP:-build/src/ccomp}
data=samples/measurements/hmc-laser-grid-sphere.csv
work=build/walkthrough
mkdir -p "$work"
model=samples/machines/hmc-xyzb-geometric.yaml
for step in 1 2 3 4; do
  "$ccomp" check "$data" -m "$model" > "$work/check-$step.txt"
  echo "\$ ccomp check $data -m $model"
  grep -E "^model '|^refitted|^missing effects: none|^1\. |^   term|^   rms" "$work/check-$step.txt" | head -5 | sed 's/^/  /'
  spec=$(sed -n "s/^   or: ccomp fit \.\.\. --add '\(.*\)'$/\1/p" "$work/check-$step.txt" | head -1)
  [ -z "$spec" ] && break
  echo "\$ ccomp fit $data -m $model --add '$spec' -o $work/fitted-$step.yaml"
  "$ccomp" fit "$data" -m "$model" --add "$spec" -o "$work/fitted-$step.yaml" > "$work/fit-$step.txt"
  grep -E "^  rms .* -> " "$work/fit-$step.txt" | sed 's/^/  /'
  model="$work/fitted-$step.yaml"
done
# The model the loop ends with compensates a program, and verify proves the output.
program=samples/programs/pocket-xy.ngc
echo "\$ ccomp $program -m $model --tool-table samples/tools.tbl -o $work/pocket-xy.ngc -q"
"$ccomp" "$program" -m "$model" --tool-table samples/tools.tbl -o "$work/pocket-xy.ngc" -q
echo "\$ ccomp verify $program $work/pocket-xy.ngc -m $model --tool-table samples/tools.tbl"
"$ccomp" verify "$program" "$work/pocket-xy.ngc" -m "$model" --tool-table samples/tools.tbl 2>&1 |
  sed -E 's/ \(table point [^)]*\)//; s/^/  /'
