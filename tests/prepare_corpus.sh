#!/usr/bin/env bash
# Real third-party models (Debian's assimp-testmodels, broken files
# included): every model in a format prepare reads either prepares (exit 0,
# an output file) or fails with one line on stderr, exit 1 and no output
# file; no crash, no hang. Each model twice: as it is, and with --repair.
# Usage: prepare_corpus.sh PRINTLIGHT [MODELS_DIR]
set -uo pipefail
printlight=$1
models=${2:-/usr/share/assimp/models}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
failures=0 prepared=0 refused=0 repaired=0
while IFS= read -r -d '' model; do
 for repair in "" --repair; do
  out="$work/out.vdb"
  timeout -k 5 60 "$printlight" prepare "$model" -o "$out" --fit-mm 10 --voxel 0.5,0.5,0.5 --quiet $repair \
    >"$work/stdout" 2>"$work/stderr"
  rc=$?
  lines=$(wc -l <"$work/stderr")
  if [ $rc -eq 0 ] && [ -s "$out" ]; then
    if [ -n "$repair" ]; then repaired=$((repaired + 1)); else prepared=$((prepared + 1)); fi
  elif [ $rc -eq 1 ] && [ "$lines" -eq 1 ] && [ ! -e "$out" ] && grep -q '^printlight: error: ' "$work/stderr"; then
    refused=$((refused + 1))
  else
    echo "FAIL ($rc, $lines stderr lines): $model $repair"
    head -3 "$work/stderr"
    failures=$((failures + 1))
  fi
  rm -f "$out" "$work"/*.tmp* 2>/dev/null
  if [ -n "$(ls -A "$work" | grep -v -e '^stdout$' -e '^stderr$')" ]; then
    echo "FAIL: files left behind by $model: $(ls "$work")"
    failures=$((failures + 1))
    find "$work" -mindepth 1 -not -name stdout -not -name stderr -delete
  fi
 done
done < <(find "$models" -type f \( -iname '*.gltf' -o -iname '*.glb' -o -iname '*.obj' -o -iname '*.stl' \
                                    -o -iname '*.ply' -o -iname '*.3mf' \) -print0 | sort -z)
echo "corpus: $prepared prepared as they are, $repaired with --repair; $refused refusals of one line; $failures failed"
[ $prepared -gt 0 ] && [ $repaired -gt $prepared ] && [ $failures -eq 0 ]
