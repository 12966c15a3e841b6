#!/usr/bin/env bash
# Installs what ccomp builds and tests with, from Debian 12's packages only. Skips apt when
# everything is there already. --fuzz adds clang and libFuzzer for tools/fuzz.sh (the
# sanitizer build, tools/sanitize.sh, uses GCC's own ASan and UBSan).
set -euo pipefail
packages=(cmake ninja-build g++ pkg-config
          libeigen3-dev libcli11-dev libfmt-dev libyaml-cpp-dev tao-pegtl-dev
          libgtest-dev libgmock-dev libbenchmark-dev bc time
          # headless Chromium renders the HTML report in its test
          chromium
          # the FreeCAD post's and the Fusion 360 hook's tests (tests/cli/integration_test.cpp)
          python3 nodejs
          # what LinuxCNC's rs274 (the differential-test oracle) links against
          libpython3.11 libedit2 libtirpc3)
if [ "${1:-}" = --fuzz ]; then packages+=(clang libclang-rt-14-dev); fi
missing=()
for p in "${packages[@]}"; do dpkg -s "$p" >/dev/null 2>&1 || missing+=("$p"); done
if [ ${#missing[@]} -gt 0 ]; then
  sudo=""
  [ "$(id -u)" -eq 0 ] || sudo="sudo"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi
