# Sourced by the bench/ scripts: run from the repository root, with the build's binaries and
# a scratch folder for generated programs and outputs (BUILD overrides the build folder).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
build=${BUILD:-build}
ccomp=$build/src/ccomp
rs274=$build/rs274/rs274
work=$build/bench-work
mkdir -p "$work"

# The generated finishing pass of N lines (bench/generate_program.cpp) in $work, written
# unless there: its path. One written before the generator went back over the surface past
# 4M lines runs off the HMC's Y travel, so a long one without the lift is written again.
generated_program() {
  local n=$1 f="$work/finishing-$1.ngc"
  if [ ! -f "$f" ] || { [ "$n" -gt 4000000 ] && ! grep -q '^G0 Z5$' "$f"; }; then
    "$build/bench/ccomp_bench_generate" "$n" "$f"
  fi
  echo "$f"
}
