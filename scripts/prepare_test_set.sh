#!/usr/bin/env bash
# Prepares the whole test set (Brecka 2021, table 3.1 in kind) into
# data/grids/ with ready-to-render scenes in data/scenes/testset/, and prints
# each model's summary. The 40 mm bone takes ~35 s and ~2 GB of memory.
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
[ -f data/models/cube10.gltf ] || "$build"/make-test-data data/models
mkdir -p data/scenes/testset
for model in cube10 cube10_greek cube20 cube20_greek animal animal_spotted bone; do
  "$build"/printlight prepare "data/models/$model.gltf" -o "data/grids/$model.vdb" --quiet \
    --materials data/materials/resins_illustrative.json --scene-out "data/scenes/testset/$model"
done
