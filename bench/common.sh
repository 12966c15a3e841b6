# Sourced by the bench/ scripts: run from the repository root, with the build's binaries and
# a scratch folder for generated programs and outputs (BUILD overrides the build folder).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
build=${BUILD:-build}
ccomp=$build/src/ccomp
rs274=$build/rs274/rs274
work=$build/bench-work
mkdir -p "$work"
