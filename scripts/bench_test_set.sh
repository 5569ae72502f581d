#!/bin/sh
# Equal-error speed-up of printpt over volpath on every test-set scene,
# surface-voxel sensor, with each render's own variance as its expected
# squared error (printlight bench --self-variance; 4 spp each).
# Needs scripts/prepare_test_set.sh first. Writes out/bench/testset_*.{md,csv,svg}.
# Usage: [BENCH_SPP=N] scripts/bench_test_set.sh [CONFIGS] [MODELS...]
# (BENCH_SPP fixes the samples per pixel, e.g. 2 for the large scenes.)
set -eu
cd "$(dirname "$0")/.."
configs=${1:-volpath,printpt}
[ $# -gt 0 ] && shift
models=${*:-cube10 cube10_greek cube10_clear animal animal_spotted cube20 cube20_greek bone}
mkdir -p out/bench
for m in $models; do
    scene=data/scenes/testset/${m}_surface.json
    [ -f "$scene" ] || { echo "bench_test_set: $scene is missing: run scripts/prepare_test_set.sh" >&2; exit 1; }
    build/printlight bench "$scene" --self-variance --budgets 1 ${BENCH_SPP:+--spp $BENCH_SPP} \
        --configs "$configs" --out "out/bench/testset_$m" |
        sed -n "s/^| \([a-z].*\)/$m | \1/p"
done
