#!/usr/bin/env bash
# Regenerates the golden tileset of the current format version and its expected summary.
# Run after an intentional change to the builder's output, review the diff of the .json, and
# commit both. Old versions' goldens are never regenerated: they prove old files still read.
set -euo pipefail
cd "$(dirname "$0")/.."
terralod=${TERRALOD:-build/release/apps/terralod/terralod}
# Static builds write version 7 by default (gully: RTIN chunks stored as their bintree, the
# generated colour made by the shader from a shade layer). With --chunk-codec meshopt they write
# version 6 textured (gully), version 5 with --bake-colour (the colour stored; chunks may share
# their parent's texture) and version 4 without textures (gully-untextured). Versions 1 to 3,
# and version 4 textured, are no longer written: their goldens stay as they are.
for name in gully gully-v6 gully-baked gully-untextured; do
  out=tests/data/golden/v7
  extra=()
  [ "$name" = gully-v6 ] && out=tests/data/golden/v6 && extra=(--chunk-codec meshopt)
  [ "$name" = gully-baked ] && out=tests/data/golden/v5 && extra=(--chunk-codec meshopt --bake-colour)
  [ "$name" = gully-untextured ] && out=tests/data/golden/v4 && extra=(--chunk-codec meshopt --no-texture)
  [ "$name" = gully-baked ] || [ "$name" = gully-v6 ] && name=gully
  mkdir -p "$out"
  "$terralod" build tests/data/landlab_west_bijou_gully_3m.asc -o "$out/$name.tlod" \
    --max-error 0.25 --threads 1 "${extra[@]}"
  "$terralod" info "$out/$name.tlod" --json > "$out/$name.json"
  echo "updated $out/$name.tlod and $out/$name.json"
done
# VIPM tilesets (mesh kind 2, written as version 2: a normal map per node).
out=tests/data/golden/vipm
mkdir -p "$out"
"$terralod" build tests/data/landlab_west_bijou_gully_3m.asc -o "$out/gully.tlod" \
  --kind vipm --max-error 0.25 --threads 1
"$terralod" info "$out/gully.tlod" --json > "$out/gully.json"
echo "updated $out/gully.tlod and $out/gully.json"
