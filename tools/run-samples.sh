#!/usr/bin/env bash
# Runs the main job on samples/: each program with each machine model, into build/samples-out/
# (CCOMP picks the command, CCOMP_SAMPLES_OUT the folder: ctest passes its build's own).
set -euo pipefail
cd "$(dirname "$0")/.."
ccomp=${CCOMP:-build/src/ccomp}
out_root=${CCOMP_SAMPLES_OUT:-build/samples-out}
for model in samples/machines/*.yaml; do
  name=$(basename "$model" .yaml)
  out="$out_root/$name"
  mkdir -p "$out"
  # The full HMC model has thermal terms: give it the sensor readings of a warm machine.
  extra=()
  grep -q '^sensors:' "$model" && extra=(--sensor bed=24 --sensor column=23 --sensor spindle=31 --time 3600)
  # The 3-axis and trunnion machines have no B: they take the programs without a B word.
  programs=(samples/programs/*.ngc)
  if ! grep -q '^  B:' "$model" && [ "$name" != zero ]; then
    programs=(samples/programs/pocket-xy.ngc samples/programs/profile-g41.ngc)
  fi
  "$ccomp" "${programs[@]}" -m "$model" --out-dir "$out" \
    --tool-table samples/tools.tbl -j "$(nproc)" "${extra[@]}"
  echo "ccomp: samples/programs/*.ngc with $model -> $out/"
done
