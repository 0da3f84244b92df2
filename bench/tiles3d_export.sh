#!/usr/bin/env bash
# 3D Tiles export (issue 24), figures for docs/benchmarks.md "3D Tiles export":
#  1. export time, peak memory and bytes against the .tlod: Zion with its Landsat image and
#     untextured, the 8193² synth with its generated colour and untextured (auto tiling: the
#     synth's 21,845 chunks get implicit tiling), and Zion's explicit and implicit trees;
#  2. for three views of Zion, the tiles CesiumJS requests and draws at maximumScreenSpaceError
#     = tau (scripts/cesium-screenshot.sh) against the chunks `terralod render` selects at the
#     same tau, size and field of view.
#
#   bench/tiles3d_export.sh          scratch in $BENCH_DIR/tiles3d (default build/bench)
# ONLY="export" or ONLY="cesium" runs one part. Needs `make` first (and scripts/install-deps.sh
# for CesiumJS and Chromium).
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
terralod=${TERRALOD:-$here/build/release/apps/terralod/terralod}
export TERRALOD=$terralod
dir=${BENCH_DIR:-$here/build/bench}/tiles3d
data=$here/tests/data
mkdir -p "$dir"
cd "$dir"
want() { [ -z "${ONLY:-}" ] || [[ " $ONLY " == *" $1 "* ]]; }

[ -e zion.tlod ] || "$terralod" build "$data/zion_srtm3_utm12_30m.tif" \
  --texture "$data/zion_landsat8_rgb_utm12_30m.tif" -o zion.tlod >/dev/null
[ -e zion_plain.tlod ] || "$terralod" build "$data/zion_srtm3_utm12_30m.tif" --no-texture \
  -o zion_plain.tlod >/dev/null

# One export: wall seconds, peak RSS, tiles and bytes, against the tileset's bytes.
export_row() {
  local name=$1 tileset=$2
  shift 2
  rm -rf "$name.3dtiles"
  /usr/bin/time -f "%e %M" -o time.txt "$terralod" export "$tileset" --format 3dtiles "$@" \
    -o "$name.3dtiles" >export.txt 2>/dev/null
  read -r wall rss <time.txt
  local bytes tlod
  bytes=$(du -sb "$name.3dtiles" | cut -f1)
  tlod=$(stat -c %s "$tileset")
  printf '| %s | %s | %s | %.1f | %d | %s | %.3f | %s |\n' "$name" "$*" \
    "$(sed -E 's/.*: ([0-9]+) tiles,.*/\1/' export.txt)" "$wall" "$((rss / 1024))" "$bytes" \
    "$(awk -v a="$bytes" -v b="$tlod" 'BEGIN { print a / b }')" \
    "$(sed -nE 's/.*\((implicit quadtree tiling, [0-9]+ subtree files)[^)]*\).*/\1/p; s/.*\(an explicit tree\).*/explicit/p' export.txt)"
}

if want export; then
  [ -e s8193.tif ] || "$terralod" synth --size 8193 -o s8193.tif >/dev/null
  [ -e s8193.tlod ] || "$terralod" build s8193.tif -o s8193.tlod >/dev/null
  [ -e s8193_plain.tlod ] || "$terralod" build s8193.tif --no-texture -o s8193_plain.tlod >/dev/null
  echo "| export | options | tiles | wall s | peak MB | bytes | / .tlod | tiling |"
  echo "|---|---|---:|---:|---:|---:|---:|---|"
  export_row zion zion.tlod
  export_row zion_implicit zion.tlod --tiling implicit
  export_row zion_plain zion_plain.tlod
  [ -e zion_vipm.tlod ] || "$terralod" build "$data/zion_srtm3_utm12_30m.tif" --kind vipm -o zion_vipm.tlod >/dev/null
  export_row zion_vipm zion_vipm.tlod
  export_row s8193 s8193.tlod
  export_row s8193_plain s8193_plain.tlod
fi

if want cesium; then
  rm -rf zion_view.3dtiles
  "$terralod" export zion.tlod --format 3dtiles -o zion_view.3dtiles >/dev/null
  echo "| view | eye | target | terralod chunks | CesiumJS tiles drawn | requested | load s |"
  echo "|---|---|---|---:|---:|---:|---:|"
  for view in "test|12000,2000,3500|20000,20000,1600" "overview|17000,-12000,16000|17000,21000,1500" \
    "low|15000,8000,2300|19000,16000,1700"; do
    IFS='|' read -r name eye target <<<"$view"
    chunks=$("$terralod" render zion.tlod --eye "$eye" --target "$target" --size 640x480 \
      --tau 2 -o "terralod_$name.png" | sed -E 's/.*: ([0-9]+) chunks,.*/\1/')
    stats=$("$here/scripts/cesium-screenshot.sh" zion_view.3dtiles --eye "$eye" --target "$target" \
      --size 640x480 --tau 2 -o "cesium_$name.png")
    field() { node -e 'console.log(JSON.parse(process.argv[1])[process.argv[2]])' "$stats" "$1"; }
    printf '| %s | %s | %s | %s | %s | %s | %.1f |\n' "$name" "$eye" "$target" "$chunks" \
      "$(field tiles_drawn)" "$(field tiles_requested)" "$(awk -v ms="$(field load_ms)" 'BEGIN { print ms / 1000 }')"
  done
fi
