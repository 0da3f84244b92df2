#!/usr/bin/env bash
# Horizon culling changes no pixel and opens no hole (issue 19 item 6). Over each DEM, two
# flights: the auto-flight's climb, and the first FRAMES frames of the whole auto flight (its
# low pass first). For each:
#   - `render` every EVERY-th frame with and without culling (complete frames), the PNGs
#     compared byte for byte;
#   - `bench` with culling and --source: holes_total (bench's look-down hole count, which
#     culls too), culled chunks and triangles per frame.
#
#   bench/horizon_culling.sh     (ONLY="name ..." restricts; SIZE=320x240, FRAMES=2000,
#                                 EVERY=25, TAU=2; BENCH_DIR=build/bench)
#
# One Markdown row per flight; files in $BENCH_DIR/horizon.
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
terralod=${TERRALOD:-$here/build/release/apps/terralod/terralod}
dir=${BENCH_DIR:-$here/build/bench}/horizon
data=$here/tests/data
size=${SIZE:-320x240}
frames=${FRAMES:-2000}
every=${EVERY:-25}
tau=${TAU:-2}
mkdir -p "$dir"

source_of() {
  case $1 in
    rainier) echo "$data/osgearth_mt_rainier_90m.tif" ;;
    n43w123) echo "$data/N43W123.hgt" ;;
    crater) echo "$data/crater_lake_0513.bt" ;;
    zion) echo "$data/zion_srtm3_utm12_30m.tif" ;;
    vancouver) echo "$data/srtm3_vancouver_n49w124_n49w123.tif" ;;
    frontrange) echo "$data/landlab_srtmgl3_frontrange.asc" ;;
    nz) echo "$data/nz_elev_1km.tif" ;;
    burrard) echo "$data/burrard_inlet_srtm3.tif" ;;
    gully) echo "$data/landlab_west_bijou_gully_3m.asc" ;;
  esac
}

echo "| DEM | flight | frames | images differing (of rendered) | holes_total | culled_chunks_p50 / max | culled_triangles_p50 / max | chunks_p50 |"
echo "|---|---|---|---|---|---|---|---|"
for name in rainier n43w123 crater zion vancouver frontrange nz burrard gully; do
  if [ -n "${ONLY:-}" ] && [[ " $ONLY " != *" $name "* ]]; then continue; fi
  source=$(source_of "$name")
  [ -f "$dir/$name.tlod" ] || "$terralod" build "$source" -o "$dir/$name.tlod" >/dev/null
  for flight in climb low; do
    if [ $flight = climb ]; then fly=(--auto-flight --climb-only); else fly=(--auto-flight --frames "$frames"); fi
    common=("$dir/$name.tlod" "${fly[@]}" --size "$size" --tau "$tau")
    on=$dir/${name}_${flight}_on off=$dir/${name}_${flight}_off
    rm -rf "$on" "$off"
    mkdir -p "$on" "$off"
    "$terralod" render "${common[@]}" --every "$every" --frames-dir "$on" >/dev/null
    "$terralod" render "${common[@]}" --every "$every" --frames-dir "$off" --no-horizon-culling >/dev/null
    rendered=0 differing=0
    for f in "$on"/frame_*.png; do
      rendered=$((rendered + 1))
      cmp -s "$f" "$off/$(basename "$f")" || differing=$((differing + 1))
    done
    out=$dir/${name}_${flight}.json
    "$terralod" bench "${common[@]}" --source "$source" --json "$out" >/dev/null
    python3 - "$out" "$name" "$flight" "$differing" "$rendered" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
print(f"| {sys.argv[2]} | {sys.argv[3]} | {d['frames']} | {sys.argv[4]} of {sys.argv[5]} | "
      f"{d['holes_total']} | {d['culled_chunks_p50']:g} / {d['culled_chunks_max']:g} | "
      f"{d['culled_triangles_p50']:g} / {d['culled_triangles_max']:g} | {d['chunks_p50']:g} |")
PY
  done
done
