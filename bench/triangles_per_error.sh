#!/usr/bin/env bash
# Triangles per level of terralod tilesets (`--mesher rtin`, the default, and `--mesher greedy`)
# against what two reference meshers need for the whole raster at each level's error δ(L)
# (bench/triangles_per_error.mjs: npm delatin, the same exact bound at every sample; npm
# @mapbox/martini, RTIN with midpoint errors). Prints a markdown table; docs/benchmarks.md
# "Triangles per error" has the figures.
#
#   bench/triangles_per_error.sh DEM [terralod build options...]
#   e.g. bench/triangles_per_error.sh tests/data/crater_lake_0513.bt --max-error 1
#
# Needs node and the npm tools in tests/tools (scripts/install-deps.sh), gdal_translate, and
# a DEM without voids (the meshers know nothing of them).
set -euo pipefail
cd "$(dirname "$0")/.."
terralod=${TERRALOD:-build/release/apps/terralod/terralod}
dem=$1
shift
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

"$terralod" build "$dem" -o "$work/t.tlod" --no-texture "$@" >&2
"$terralod" info "$work/t.tlod" --json >"$work/info.json"
"$terralod" build "$dem" -o "$work/g.tlod" --no-texture --mesher greedy "$@" >&2
"$terralod" info "$work/g.tlod" --json >"$work/greedy.json"
gdal_translate -q -of ENVI -ot Float32 "$dem" "$work/heights.f32"
read -r width height < <(python3 -c 'import json,sys; s=json.load(open(sys.argv[1]))["source_size"]; print(s[0], s[1])' "$work/info.json")
errors=$(python3 -c 'import json,sys; print(" ".join(str(l["error"]) for l in json.load(open(sys.argv[1]))["per_level"]))' "$work/info.json")
# shellcheck disable=SC2086  # one argument per error
node bench/triangles_per_error.mjs "$work/heights.f32" "$width" "$height" $errors >"$work/npm.json"
python3 - "$work/info.json" "$work/greedy.json" "$work/npm.json" "$dem" <<'PY'
import json, sys
info, greedy, npm = (json.load(open(a)) for a in sys.argv[1:4])
dem = sys.argv[4]
print(f"{dem} ({info['source_size'][0]} x {info['source_size'][1]}):\n")
print("| level | δ(L) m | chunks | rtin | greedy | greedy / rtin | delatin | rtin / delatin | greedy / delatin | martini | rtin / martini |")
print("|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
for l, g, d, m in zip(info["per_level"], greedy["per_level"], npm["delatin"], npm["martini"]):
    ours, gr = l["triangles"], g["triangles"]
    mart = f"{m:,} | {ours / m:.2f}" if m else "– | –"
    print(f"| {l['level']} | {l['error']:g} | {l['chunks']:,} | {ours:,} | {gr:,} | {gr / ours:.2f} | {d:,} | {ours / d:.2f} | {gr / d:.2f} | {mart} |")
PY
