#!/usr/bin/env bash
# The README's second command: install, build, fetch LinuxCNC's rs274 for the differential
# tests, run every test (ctest), then the main job on the samples. The suite runs once, in
# the sanitized build (tools/sanitize.sh: build-asan/, -O2 like Release, under AddressSanitizer
# and UndefinedBehaviorSanitizer): a second, plain build of the same code would double CI's
# time and catch nothing the sanitized one misses. tools/setup.sh builds Release (build/).
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/install-deps.sh
bash tools/sanitize.sh
CCOMP=build-asan/src/ccomp CCOMP_SAMPLES_OUT=build-asan/samples-out bash tools/run-samples.sh
