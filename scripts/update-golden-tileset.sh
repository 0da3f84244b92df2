#!/usr/bin/env bash
# Regenerates the golden tileset of the current format version and its expected summary.
# Run after an intentional change to the builder's output, review the diff of the .json, and
# commit both. Old versions' goldens are never regenerated: they prove old files still read.
set -euo pipefail
cd "$(dirname "$0")/.."
terralod=${TERRALOD:-build/release/apps/terralod/terralod}
# Version 1 is what untextured builds write; version 3 is what textured ones write (version 2,
# textures stored as they are, is no longer written: its golden stays as it is).
for version in v1 v3; do
  out=tests/data/golden/$version
  mkdir -p "$out"
  extra=()
  [ "$version" = v1 ] && extra=(--no-texture)
  "$terralod" build tests/data/landlab_west_bijou_gully_3m.asc -o "$out/gully.tlod" \
    --max-error 0.25 --threads 1 "${extra[@]}"
  "$terralod" info "$out/gully.tlod" --json > "$out/gully.json"
  echo "updated $out/gully.tlod and $out/gully.json"
done
# VIPM tilesets (mesh kind 2, written as version 2: a normal map per node).
out=tests/data/golden/vipm
mkdir -p "$out"
"$terralod" build tests/data/landlab_west_bijou_gully_3m.asc -o "$out/gully.tlod" \
  --kind vipm --max-error 0.25 --threads 1
"$terralod" info "$out/gully.tlod" --json > "$out/gully.json"
echo "updated $out/gully.tlod and $out/gully.json"
