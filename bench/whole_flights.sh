#!/usr/bin/env bash
# The whole automatic flight (low pass and climb) over every bundled real DEM and a 4097² synth,
# with morphing and skirts on, every source sample measured. Hours per DEM here (the low pass is
# up to ~32,000 frames); run it in the background. Uses the tilesets bench/render_quality.sh builds.
#
#   bench/whole_flights.sh [TAU] [SIZE]     defaults: 2 320x240
#
# ONLY="name ..." restricts the DEMs (synth_4097_10m is the 4097² synth at 10 m, made here when
# missing). One Markdown row per DEM; JSON in $BENCH_DIR/quality.
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
tau=${1:-2}
size=${2:-320x240}
terralod=${TERRALOD:-$here/build/release/apps/terralod/terralod}
dir=${BENCH_DIR:-$here/build/bench}/quality
data=$here/tests/data
files=(landlab_west_bijou_gully_3m.asc gzcommon_dem_squared_129.tif landlab_srtmgl3_frontrange.asc
       crater_lake_0513.bt zion_srtm3_utm12_30m.tif zion_srtm3.tif osgearth_mt_rainier_90m.tif
       N43W123.hgt nz_elev_1km.tif loadersgl_terrarium_256.png synth_4097_10m.tif)
echo "| DEM | frames | max_error_px | max_pop_px | holes_total | frame_ms_p50 | triangles_p50 |"
echo "|---|---|---|---|---|---|---|"
for file in "${files[@]}"; do
  name=${file%%.*}
  if [ -n "${ONLY:-}" ] && [[ " $ONLY " != *" $name "* ]]; then continue; fi
  source=$data/$file
  if [ "$name" = synth_4097_10m ]; then
    source=$dir/$file
    [ -f "$source" ] || "$terralod" synth --size 4097 --spacing 10 -o "$source" >/dev/null
    [ -f "$dir/$name.tlod" ] || "$terralod" build "$source" --no-texture -o "$dir/$name.tlod" >/dev/null
  fi
  if [ ! -f "$dir/$name.tlod" ]; then
    echo "$dir/$name.tlod: missing; run bench/render_quality.sh first" >&2
    exit 1
  fi
  out=$dir/${name}_whole.json
  "$terralod" bench "$dir/$name.tlod" --auto-flight --tau "$tau" --size "$size" \
    --source "$source" --json "$out" >/dev/null
  python3 - "$out" "$name" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
print(f"| {sys.argv[2]} | {d['frames']} | {d['max_error_px']:.3f} | {d['max_pop_px']:.4f} | "
      f"{d['holes_total']} | {d['frame_ms_p50']:.1f} | {d['triangles_p50']:.0f} |")
PY
done
