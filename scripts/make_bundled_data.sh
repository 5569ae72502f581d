#!/usr/bin/env bash
# Generates the bundled data that is not committed: the procedural test-set
# models (data/models/) and the label grids of the two default 10 mm cubes
# (data/grids/), with the programs in BUILD_DIR (default: build).
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
"$build"/make-test-data data/models
"$build"/printlight prepare data/meshes/cube10.obj -o data/grids/cube10_white.vdb --quiet
"$build"/printlight prepare data/models/cube10_greek.gltf -o data/grids/cube10_greek.vdb --quiet
