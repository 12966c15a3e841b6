#!/usr/bin/env bash
# Runs the main job on samples/: each program with each machine model, into build/samples-out/.
set -euo pipefail
cd "$(dirname "$0")/.."
ccomp=${CCOMP:-build/src/ccomp}
for model in samples/machines/*.yaml; do
  name=$(basename "$model" .yaml)
  out="build/samples-out/$name"
  mkdir -p "$out"
  "$ccomp" samples/programs/*.ngc -m "$model" --out-dir "$out" \
    --tool-table samples/tools.tbl -j "$(nproc)"
  echo "ccomp: samples/programs/*.ngc with $model -> $out/"
done
