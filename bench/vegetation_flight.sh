#!/usr/bin/env bash
# Issue 23's figures: vegetation over the terrain (docs/benchmarks.md, "Vegetation over the
# terrain").
#
#  1. The low flight over the 4097² synth (seed 1, 5 m) with sunflowers at 1024×768
#     (bench/flights/vegetation_low.json: 900 frames, 3 m above the valley floor, 1.5 cm a
#     frame as a 60 fps flight at 0.5 % of its height, the heading turning 60°): frame time p50/p99, the warp, the composite, splats, LDI tiles,
#     memory, pops from the LDI choices; against the ray-traced truth every 60th frame (SSIM,
#     coverage error, with pictures in the report); terrain figures against the source.
#  2. The same flight with --no-vegetation-blend (the pops blending hides) and without
#     vegetation (what the terrain alone costs, in the same run).
#  3. The meadow over the same flight.
#  4. The terrain's figures with and without sunflowers on a tileset built at 0.07 m.
#
#   bench/vegetation_flight.sh
#
# Needs bench/vegetation.sh's bakes (it makes them when missing). Scratch: $BENCH_DIR/vegetation.
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
terralod=${TERRALOD:-$here/build/release/apps/terralod/terralod}
dir=${BENCH_DIR:-$here/build/bench}/vegetation
flight=$here/bench/flights/vegetation_low.json
mkdir -p "$dir"

for scene in sunflowers meadow; do
  [ -f "$dir/$scene.tlv" ] || "$terralod" vegetation bake --scene $scene -o "$dir/$scene.tlv"
done
if [ ! -f "$dir/synth4097.tlod" ]; then
  "$terralod" synth --size 4097 --spacing 5 --seed 1 -o "$dir/synth4097.tif"
  "$terralod" build "$dir/synth4097.tif" -o "$dir/synth4097.tlod"
fi

echo "== 1. sunflowers, the low flight, with the ground truth every 60th frame"
"$terralod" bench "$dir/synth4097.tlod" --flight "$flight" --source "$dir/synth4097.tif" \
  --vegetation "$dir/sunflowers.tlv" --vegetation-reference --reference-every 60 \
  --json "$dir/flight_sunflowers.json" --report "$dir/report_sunflowers"

echo "== 2. the same without blending, and without vegetation"
"$terralod" bench "$dir/synth4097.tlod" --flight "$flight" --vegetation "$dir/sunflowers.tlv" \
  --no-vegetation-blend --json "$dir/flight_no_blend.json"
"$terralod" bench "$dir/synth4097.tlod" --flight "$flight" --source "$dir/synth4097.tif" \
  --json "$dir/flight_terrain.json"

echo "== 3. the meadow"
"$terralod" bench "$dir/synth4097.tlod" --flight "$flight" --vegetation "$dir/meadow.tlv" \
  --vegetation-reference --reference-every 150 --json "$dir/flight_meadow.json"

echo "== 4. terrain figures with and without sunflowers on a tileset of the finest error 16-bit"
echo "==    heights allow here (the default tileset's 1 m cannot hold tau 3 m above the ground)"
[ -f "$dir/synth4097_fine.tlod" ] ||
  "$terralod" build "$dir/synth4097.tif" -o "$dir/synth4097_fine.tlod" --max-error 0.07 --no-texture
"$terralod" bench "$dir/synth4097_fine.tlod" --flight "$flight" --source "$dir/synth4097.tif" \
  --json "$dir/flight_fine_terrain.json"
"$terralod" bench "$dir/synth4097_fine.tlod" --flight "$flight" --source "$dir/synth4097.tif" \
  --vegetation "$dir/sunflowers.tlv" --json "$dir/flight_fine_sunflowers.json"

python3 - "$dir" <<'PY'
import json, sys
d = sys.argv[1]
keys = ["frame_ms_p50", "frame_ms_p99", "vegetation_ms_p50", "vegetation_ms_p99",
        "composite_ms_p50", "splats_p50", "ldi_tiles_p50", "vegetation_resident_mb",
        "vegetation_pop_mean", "vegetation_pop_mean_avg", "vegetation_ssim_mean",
        "vegetation_ssim_min", "vegetation_coverage_error", "max_error_px", "holes_total",
        "image_pop_mean"]
for run in ["flight_sunflowers", "flight_no_blend", "flight_terrain", "flight_meadow",
            "flight_fine_terrain", "flight_fine_sunflowers"]:
    j = json.load(open(f"{d}/{run}.json"))
    print(run, " ".join(f"{k}={j[k]:.4g}" for k in keys if k in j))
PY
