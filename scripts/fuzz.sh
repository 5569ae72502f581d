#!/usr/bin/env bash
# Fuzzes the input readers with libFuzzer (clang from Debian): scene JSON and
# batch manifests, material tables, LabelGrid .bin and Mitsuba .vol. Each
# target runs a fixed number of inputs from seeds made of the bundled files;
# a crash, sanitizer report, uncaught exception, hang (> 10 s) or > 2 GB RSS
# stops it and leaves the input in build-fuzz/findings/.
# Usage: scripts/fuzz.sh [RUNS_PER_TARGET]   (default 100000)
set -euo pipefail
cd "$(dirname "$0")/.."
runs=${1:-100000}

missing=()
for p in clang libclang-rt-14-dev; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  sudo=""
  [ "$(id -u)" -eq 0 ] || sudo="sudo"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

CXX=clang++ cmake -S . -B build-fuzz -DCMAKE_BUILD_TYPE=RelWithDebInfo -DPRINTLIGHT_FUZZ=ON \
  -DPRINTLIGHT_BUILD_TESTS=OFF >/dev/null
cmake --build build-fuzz -j"$(nproc)" --target fuzz_scene_json fuzz_materials_json fuzz_label_grid

# Seeds: the bundled JSON files, and tiny grids written with perl (always in
# Debian): the first byte picks .bin (0) or .vol (1) in fuzz_label_grid.
seeds=build-fuzz/seeds
rm -rf "$seeds" && mkdir -p "$seeds"/{scene,materials,grid} build-fuzz/findings
cp data/scenes/*.json data/batch/*.json "$seeds/scene/"
cp data/materials/*.json "$seeds/materials/"
perl -e 'print pack("C l<3 d<6 C8", 0, 2,2,2, 0,0,0, 1,1,1, 4,4,4,4,1,4,4,5)' >"$seeds/grid/bin"
perl -e 'print pack("C a3 C l< l<3 l< f<6 C8", 1, "VOL",3, 3, 2,2,2, 1, 0,0,0,1,1,1, 4,4,4,4,1,4,4,5)' >"$seeds/grid/vol_u8"
perl -e 'print pack("C a3 C l< l<3 l< f<6 f<8", 1, "VOL",3, 1, 2,2,2, 1, 0,0,0,1,1,1, 4,4,4,4,1,4,4,5)' >"$seeds/grid/vol_f32"

export ASAN_OPTIONS=detect_leaks=1:allocator_may_return_null=0
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
status=0
for spec in fuzz_scene_json:scene:8192 fuzz_materials_json:materials:8192 fuzz_label_grid:grid:4096; do
  IFS=: read -r target corpus maxlen <<<"$spec"
  mkdir -p "build-fuzz/corpus/$corpus"
  echo "fuzz: $target, $runs runs"
  if build-fuzz/tests/fuzz/$target -runs="$runs" -max_len="$maxlen" -timeout=10 -rss_limit_mb=2048 \
      -artifact_prefix=build-fuzz/findings/"$target"- -print_final_stats=1 \
      "build-fuzz/corpus/$corpus" "$seeds/$corpus" >"build-fuzz/$target.log" 2>&1; then
    grep -E "stat::number_of_executed_units|stat::peak_rss_mb|cov:" "build-fuzz/$target.log" | tail -3
  else
    status=1
    echo "fuzz: $target FOUND A PROBLEM (build-fuzz/$target.log, build-fuzz/findings/)"
    tail -30 "build-fuzz/$target.log"
  fi
done
exit $status
