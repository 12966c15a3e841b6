#!/usr/bin/env bash
# The README's second command: install, build, fetch LinuxCNC's rs274 for the differential
# tests, run every test (ctest), then the main job on the samples.
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/install-deps.sh
bash tools/build.sh
bash tools/rs274/fetch.sh build/rs274
ctest --test-dir build --output-on-failure -j"$(nproc)"
bash tools/run-samples.sh
