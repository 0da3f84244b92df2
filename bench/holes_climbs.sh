#!/usr/bin/env bash
# The auto-flight climbs where one-pixel holes were reported (issue 18), at 640x480 and tau 2,
# every source sample measured: the Vancouver mosaic (two SRTM tiles), the Alps (7 % voids),
# a synthetic DEM of a global grid's size and spacing (4320 x 2161 cells of 9,266 m, built
# with --max-error 25), the flat plain at 64.8 N and the bundled Zion DEM. Tens of minutes per
# climb here; run it in the background.
#
#   bench/holes_climbs.sh        (ONLY="name ..." restricts; SHARED= the folder of the
#                                 shared DEMs, default ../shared/data beside the checkout)
#
# One Markdown row per climb; JSON in $BENCH_DIR/holes.
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
terralod=${TERRALOD:-$here/build/release/apps/terralod/terralod}
dir=${BENCH_DIR:-$here/build/bench}/holes
shared=${SHARED:-$here/../shared/data}
data=$here/tests/data
mkdir -p "$dir"

source_of() {
  case $1 in
    vancouver) echo "$data/srtm3_vancouver_n49w124_n49w123.tif" ;;
    alps) echo "$shared/N46E008.tif" ;;
    global) echo "$dir/global_4320x2161_9266m.tif" ;;
    flat64n) echo "$data/n43w123_flat_64n.tif" ;;
    zion) echo "$data/zion_srtm3_utm12_30m.tif" ;;
  esac
}

echo "| climb | frames | holes_total | max_error_px | max_error_px_all | easing_frames | coarser_than_wanted_frames |"
echo "|---|---|---|---|---|---|---|"
for name in vancouver alps global flat64n zion; do
  if [ -n "${ONLY:-}" ] && [[ " $ONLY " != *" $name "* ]]; then continue; fi
  source=$(source_of "$name")
  build=()
  if [ "$name" = global ]; then
    build=(--max-error 25)
    if [ ! -f "$source" ]; then
      "$terralod" synth --size 4321 --spacing 9266 -o "$dir/global_4321.tif" >/dev/null
      gdal_translate -q -srcwin 0 0 4320 2161 "$dir/global_4321.tif" "$source"
      rm -f "$dir/global_4321.tif"
    fi
  fi
  [ -f "$dir/$name.tlod" ] || "$terralod" build "$source" "${build[@]}" -o "$dir/$name.tlod" >/dev/null
  out=$dir/$name.json
  "$terralod" bench "$dir/$name.tlod" --auto-flight --climb-only --size 640x480 --tau 2 \
    --source "$source" --json "$out" >/dev/null
  python3 - "$out" "$name" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
print(f"| {sys.argv[2]} | {d['frames']} | {d['holes_total']} | {d['max_error_px']:.3f} | "
      f"{d['max_error_px_all']:.3f} | {d['easing_frames']} | {d['coarser_than_wanted_frames']} |")
PY
done
