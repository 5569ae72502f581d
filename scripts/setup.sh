#!/usr/bin/env bash
# Sets printlight up on Debian 12: installs the Debian packages that are
# missing (non-interactive, idempotent, quick when all are present),
# configures and builds in Release, and generates the bundled label grids.
#
#   scripts/setup.sh           what the program needs: build/printlight, its
#                              Python module and the bundled data
#   scripts/setup.sh --tests   that and the test suite (GoogleTest, Debian's
#                              model corpus, Chromium for the report page)
set -euo pipefail
cd "$(dirname "$0")/.."

tests=0
case "${1:-}" in
  "") ;;
  --tests) tests=1 ;;
  *) echo "setup: unknown option '$1' (setup.sh [--tests])" >&2; exit 2 ;;
esac

packages=(
  cmake make g++ ccache pkg-config libcli11-dev
  libembree-dev libopenvdb-dev libboost-iostreams-dev
  libopenimageio-dev libtbb-dev
  libtinygltf-dev nlohmann-json3-dev zlib1g-dev
  pybind11-dev python3-dev python3-numpy libeigen3-dev libabsl-dev libassimp-dev libcgal-dev
  libopenmpi-dev openmpi-bin
)
((tests)) && packages+=(libgtest-dev assimp-testmodels chromium)
# The report viewer's scripts come from the npm registry (web/package.json);
# Debian's nodejs and npm where the machine has no npm.
command -v npm >/dev/null || packages+=(nodejs npm)
installed() { dpkg-query -W -f='${Status}' "$1" 2>/dev/null | grep -q "install ok installed"; }
missing=()
for p in "${packages[@]}"; do
  installed "$p" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "setup: installing ${missing[*]}"
  sudo=""
  [ "$(id -u)" -eq 0 ] || sudo="sudo"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

# three.js and esbuild for the HTML report, as web/package-lock.json pins them.
if [ ! -x web/node_modules/.bin/esbuild ] || [ web/package-lock.json -nt web/node_modules/.package-lock.json ]; then
  echo "setup: npm ci in web/"
  (cd web && npm ci --no-audit --no-fund --loglevel=error >/dev/null)
fi

# The suite is configured wherever GoogleTest is installed (a build set up
# with --tests keeps its tests), and built only when asked for.
build_tests=OFF
installed libgtest-dev && build_tests=ON
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DPRINTLIGHT_BUILD_TESTS=$build_tests >/dev/null
if ((tests)); then
  cmake --build build -j"$(nproc)"
else
  targets=(printlight make-test-data)
  # The Python module where CMake found pybind11 (CMakeLists.txt).
  grep -q '^pybind11_DIR:PATH=/' build/CMakeCache.txt && targets+=(printlight_python)
  cmake --build build -j"$(nproc)" --target "${targets[@]}"
fi

# The test-set models and the default cube grids are generated, not committed.
if [ ! -f data/grids/cube10_white.vdb ] || [ ! -f data/grids/cube10_greek.vdb ]; then
  scripts/make_bundled_data.sh build
fi
echo "setup: built build/printlight$( ((tests)) && echo ' and the test suite')"
