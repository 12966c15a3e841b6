#!/usr/bin/env bash
# Runs the main job on samples/: each program with each machine model, into build/samples-out/
# (CCOMP picks the command, CCOMP_SAMPLES_OUT the folder: ctest passes its build's own).
set -euo pipefail
cd "$(dirname "$0")/.."
ccomp=${CCOMP:-build/src/ccomp}
out_root=${CCOMP_SAMPLES_OUT:-build/samples-out}
# The rotary axis letters a program's words use (comments left out), one a line.
rotary_letters() {
  sed -e 's/([^)]*)//g' -e 's/;.*//' "$1" | grep -oE '[ABCabc][[:space:]]*[-+]?[.0-9]' | cut -c1 |
    tr abc ABC | sort -u || true
}
for model in samples/machines/*.yaml; do
  name=$(basename "$model" .yaml)
  out="$out_root/$name"
  mkdir -p "$out"
  # The full HMC model has thermal terms: give it the sensor readings of a warm machine.
  extra=()
  grep -q '^sensors:' "$model" && extra=(--sensor bed=24 --sensor column=23 --sensor spindle=31 --time 3600)
  # Each machine takes the programs whose rotary words (A B C) it has axes for: the 3-axis
  # VMC the plane programs, the HMC the B ones, the five-axis trunnion the A C ones (a
  # program naming an axis the machine lacks is refused, exit 7, as it should be). The .ngc
  # programs are LinuxCNC's dialect, the .mpf ones Siemens' (Sinumerik).
  for ext in ngc mpf; do
    programs=()
    for program in samples/programs/*."$ext"; do
      missing=0
      for letter in $(rotary_letters "$program"); do
        grep -q "^  $letter:" "$model" || missing=1
      done
      [ "$missing" = 0 ] && programs+=("$program")
    done
    [ "${#programs[@]}" -gt 0 ] || continue
    dialect=()
    [ "$ext" = mpf ] && dialect=(--dialect siemens)
    # Exit 1 is an output written whose verdict fails (the G41 profile on the full HMC keeps
    # more than the tolerance where the control's own cutter offset runs the pieces): the
    # warning says which; anything else stops the run.
    status=0
    "$ccomp" "${programs[@]}" -m "$model" --out-dir "$out" "${dialect[@]}" \
      --tool-table samples/tools.tbl -j "$(nproc)" "${extra[@]}" || status=$?
    [ "$status" = 0 ] || [ "$status" = 1 ] || exit "$status"
    echo "ccomp: samples/programs/*.$ext with $model -> $out/"
  done
done
