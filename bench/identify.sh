#!/usr/bin/env bash
# Identification speed: a fit of 100,000 observations with 300 free parameters and the
# diagnosis of the whole candidate library (targets: 2 s and 5 s).
#   bench/identify.sh    (after tools/build.sh)
source "$(dirname "$0")/common.sh"
"$build/bench/ccomp_bench_identify" 100000 15
