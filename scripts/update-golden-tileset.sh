#!/usr/bin/env bash
# Regenerates the golden tileset of the current format version and its expected summary.
# Run after an intentional change to the builder's output, review the diff of the .json, and
# commit both. Old versions' goldens are never regenerated: they prove old files still read.
set -euo pipefail
cd "$(dirname "$0")/.."
terralod=${TERRALOD:-build/release/apps/terralod/terralod}
out=tests/data/golden/v1
"$terralod" build tests/data/landlab_west_bijou_gully_3m.asc -o "$out/gully.tlod" --max-error 0.25 --threads 1
"$terralod" info "$out/gully.tlod" --json > "$out/gully.json"
echo "updated $out/gully.tlod and $out/gully.json"
