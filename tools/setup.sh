#!/usr/bin/env bash
# The README's first command: install the Debian packages, build, and run the main job on
# the shipped samples (every sample program through every sample machine model).
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/install-deps.sh
bash tools/build.sh
bash tools/run-samples.sh
