#!/usr/bin/env bash
# Prepares the whole test set (Brecka 2021, table 3.1 in kind) into
# data/grids/ with ready-to-render scenes in data/scenes/testset/, and prints
# each model's summary. The 40 mm bone takes ~35 s and ~2 GB of memory.
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
[ -f data/models/cube10_clear.vdb ] || "$build"/make-test-data data/models
mkdir -p data/scenes/testset
for model in cube10 cube10_greek cube20 cube20_greek animal animal_spotted bone; do
  "$build"/printlight prepare "data/models/$model.gltf" -o "data/grids/$model.vdb" --quiet \
    --materials data/materials/resins_illustrative.json --scene-out "data/scenes/testset/$model"
done
# The clear block: make-test-data writes its labels (prepare does not make
# clear prints); the mesh is the white cube's.
cp data/models/cube10_clear.vdb data/grids/cube10_clear.vdb
cat > data/scenes/testset/cube10_clear_surface.json <<JSON
{
  "comment": "10 mm clear block, white 4 mm core, a halftoned ring inlaid under the top face.",
  "environment": { "radiance": [1, 1, 1] },
  "object": {
    "ior": 1.5,
    "labels": "../../grids/cube10_clear.vdb",
    "materials": "../../materials/resins_illustrative.json",
    "mesh": "../../models/cube10.gltf"
  },
  "output": { "path": "out/cube10_clear_surface" },
  "render": { "channel": "rgb", "integrator": "volpath", "reentry": false, "seed": 1, "spp": 4 },
  "sensor": { "type": "surface_voxels" }
}
JSON
