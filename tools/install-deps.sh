#!/usr/bin/env bash
# Installs what ccomp builds and tests with, from Debian 12's packages, and the HTML report's
# plotting library from the npm registry (web/report, version pinned). Skips apt and npm when
# everything is there already. --fuzz adds clang and libFuzzer for tools/fuzz.sh (the
# sanitizer build, tools/sanitize.sh, uses GCC's own ASan and UBSan).
set -euo pipefail
packages=(cmake ninja-build g++ pkg-config
          libeigen3-dev libcli11-dev libfmt-dev libyaml-cpp-dev tao-pegtl-dev
          libgtest-dev libgmock-dev libbenchmark-dev bc time
          # headless Chromium renders the HTML report in its test
          chromium
          # the tests check every command's --json against docs/schemas/
          python3-jsonschema
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

# The HTML report's plotting library (plotly.js, pinned in web/report/package-lock.json),
# which the build embeds: npm (Debian's, unless node is there already) installs it there.
if ! command -v npm >/dev/null 2>&1; then
  sudo=""
  [ "$(id -u)" -eq 0 ] || sudo="sudo"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends nodejs npm
fi
report_assets="$(dirname "$0")/../web/report"
# Again only when the lock changed since the last install (a copy of it marks that).
if ! cmp -s "$report_assets/package-lock.json" "$report_assets/node_modules/.ccomp-installed-lock.json" ||
   [ ! -f "$report_assets/node_modules/plotly.js-dist-min/plotly.min.js" ]; then
  (cd "$report_assets" && npm ci --ignore-scripts --no-audit --no-fund --loglevel=error &&
     cp package-lock.json node_modules/.ccomp-installed-lock.json)
fi
