#!/usr/bin/env bash
# Quality of the drawn surface over every bundled real DEM: builds each (with the options the
# every-DEM test uses) and measures it with `terralod bench --source` on the automatic flight:
#  - its whole climb (about 1,000 frames, where every level merges) three ways: morphing and
#    skirts on, --no-morph, --no-skirts;
#  - the first FRAMES frames of its low pass (the whole pass is about 32,000 frames at 0.5 % of
#    the height above ground per frame), morphing and skirts on.
# One Markdown row per DEM.
#
#   bench/render_quality.sh [FRAMES] [TAU] [SIZE]     defaults: 1000 2 320x240
#
# Scratch files: $BENCH_DIR/quality. ONLY="name ..." measures just those DEMs (file names
# without extension).
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
frames=${1:-1000}
tau=${2:-2}
size=${3:-320x240}
terralod=${TERRALOD:-$here/build/release/apps/terralod/terralod}
dir=${BENCH_DIR:-$here/build/bench}/quality
mkdir -p "$dir"
data=$here/tests/data

dems=(
  "gzcommon_dem_squared_129.tif|"
  "crater_lake_0513.bt|"
  "zion_srtm3.tif|"
  "zion_srtm3_utm12_30m.tif|"
  "N43W123.hgt|--max-error 2"
  "osgearth_mt_rainier_90m.tif|--max-error 2"
  "nz_elev_1km.tif|--max-error 4"
  "landlab_srtmgl3_frontrange.asc|"
  "landlab_west_bijou_gully_3m.asc|--max-error 0.1"
  "loadersgl_terrarium_256.png|--encoding terrarium"
)
echo "| DEM | climb frames | max_error_px | max_pop_px | holes_total | max_pop_px --no-morph | holes_total --no-skirts | pass frames | pass max_error_px | pass holes_total | triangles p50 (climb) |"
echo "|---|---|---|---|---|---|---|---|---|---|---|"
for entry in "${dems[@]}"; do
  file=${entry%%|*}
  opts=${entry#*|}
  name=${file%%.*}
  if [ -n "${ONLY:-}" ] && [[ " $ONLY " != *" $name "* ]]; then continue; fi
  # shellcheck disable=SC2086
  "$terralod" build "$data/$file" -o "$dir/$name.tlod" $opts >/dev/null
  run() {
    "$terralod" bench "$dir/$name.tlod" --auto-flight --tau "$tau" --size "$size" \
      --source "$data/$file" --json "$dir/$name$1.json" "${@:2}" >/dev/null
  }
  run "" --climb-only && run "_nomorph" --climb-only --no-morph &&
    run "_noskirts" --climb-only --no-skirts && run "_pass" --frames "$frames"
  python3 - "$dir" "$name" <<'PY'
import json, sys
d, name = sys.argv[1:]
on, nomorph, noskirts, low = (json.load(open(f"{d}/{name}{k}.json"))
                              for k in ("", "_nomorph", "_noskirts", "_pass"))
print(f"| {name} | {on['frames']} | {on['max_error_px']:.3f} | {on['max_pop_px']:.4f} | "
      f"{on['holes_total']} | {nomorph['max_pop_px']:.3f} | {noskirts['holes_total']} | "
      f"{low['frames']} | {low['max_error_px']:.3f} | {low['holes_total']} | "
      f"{on['triangles_p50']:.0f} |")
PY
done
