#!/usr/bin/env bash
# Issue 22's figures: the vegetation tiles (docs/benchmarks.md, "Vegetation tiles").
#
#  1. Tiling: same-prototile neighbours and the autocorrelation of a 256×256 stochastic Wang
#     tiling beside Robinson-style hierarchical structure, the Figure-4 picture, and a
#     10,000×10,000 tiling laid by the scanline and looked up tile by tile (timed).
#  2. Placement: both scenes placed for SEEDS seeds, each laid over a 64×64 tiling: overlaps
#     (tight radii, packing radii), density near edges and corners against the interior's (within
#     twice the largest packing radius, and within 0.25 m), the density folded onto one tile as a
#     picture; and the same with --plain (the paper's round-robin, no edges and corners first).
#  3. Bake: both scenes at full quality (the paper's 468…62-pixel LDIs, 4 rays a pixel, 8
#     occlusion rays a layer): wall time, rays per second, bytes; then `info`, and the points
#     of each file over a 64×64 tiling.
#  4. Pictures: the 8 tiles of each scene from above (in context) and as their finest LDI from
#     direction 0, and one tile's LDIs at every resolution.
#
#   bench/vegetation.sh [SEEDS]     default 100
#
# Scratch files: $BENCH_DIR/vegetation; pictures also to docs/images when PICTURES=1.
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
seeds=${1:-100}
terralod=${TERRALOD:-$here/build/release/apps/terralod/terralod}
dir=${BENCH_DIR:-$here/build/bench}/vegetation
mkdir -p "$dir"

echo "== 1. tiling statistics (256x256, seed 1)"
"$terralod" vegetation tiling --size 256 --seed 1 -o "$dir/tiling_figure.png" --time 10000

echo "== 2. placement over 64x64 tilings, seeds 1..$seeds"
for scene in sunflowers meadow; do
  "$terralod" vegetation placement --scene $scene --seeds "$seeds" --tiling 64x64 \
    --density-png "$dir/${scene}_density.png"
  "$terralod" vegetation placement --scene $scene --seeds "$seeds" --tiling 64x64 --band 0.25
  echo "   the paper's plain round-robin (--plain):"
  "$terralod" vegetation placement --scene $scene --seeds "$seeds" --tiling 64x64 --plain \
    --density-png "$dir/${scene}_density_plain.png"
  "$terralod" vegetation placement --scene $scene --seeds "$seeds" --tiling 64x64 --plain --band 0.25
done

echo "== 3. bake"
for scene in sunflowers meadow; do
  start=$(date +%s.%N)
  "$terralod" vegetation bake --scene $scene -o "$dir/$scene.tlv"
  end=$(date +%s.%N)
  python3 -c "print('   whole process: %.1f s' % ($end - $start))"
  "$terralod" vegetation info "$dir/$scene.tlv"
  "$terralod" vegetation points "$dir/$scene.tlv" --tiling 64x64 --csv "$dir/${scene}_points.csv" \
    --tiles-csv "$dir/${scene}_tiles.csv"
done

echo "== 4. pictures"
for scene in sunflowers meadow; do
  "$terralod" vegetation render-tile "$dir/$scene.tlv" --tile all --view top --resolution 1 \
    -o "$dir/${scene}_tiles_top.jpg"
  "$terralod" vegetation render-tile "$dir/$scene.tlv" --tile all -o "$dir/${scene}_tiles_ldi.jpg"
  for r in 0 1 2 3 4 5 6; do
    "$terralod" vegetation render-tile "$dir/$scene.tlv" --tile 0 --resolution $r --direction 1 \
      -o "$dir/${scene}_tile0_res$r.png"
  done
done
if [ "${PICTURES:-0}" = 1 ]; then
  cp "$dir/tiling_figure.png" "$here/docs/images/vegetation_tiling_figure4.png"
  for scene in sunflowers meadow; do
    cp "$dir/${scene}_tiles_top.jpg" "$dir/${scene}_tiles_ldi.jpg" "$here/docs/images/"
    cp "$dir/${scene}_density.png" "$here/docs/images/vegetation_${scene}_density.png"
  done
  cp "$dir/sunflowers_density_plain.png" "$here/docs/images/vegetation_sunflowers_density_plain.png"
  for r in 0 2 4 6; do cp "$dir/sunflowers_tile0_res$r.png" "$here/docs/images/"; done
fi
echo "bench/vegetation.sh: results in $dir"
