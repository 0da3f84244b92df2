#!/usr/bin/env bash
# Issue 21's figures so far: fan stitching and blots on the VIPM kind.
#
#  1. Quality with fans and no flanges: each DEM's climb and the first FRAMES frames of its
#     low pass, `bench --source --stitch fans` (error, pops, holes, blot switch, fan CPU), and
#     the low pass with `--no-skirts` (no fans either: holes must appear).
#  2. Fans against flanges, and blots against --no-blots: the same low pass without --source,
#     each pair run back to back (frame time, triangles, draw calls, fan CPU per change).
#  3. The 8193² synth (1 m) at 1024×768, the first FRAMES frames of its low pass: VIPM with
#     blots and super-chunks (the default; fans, then flanges), with --no-super-chunks, with --no-blots
#     --no-super-chunks (per-chunk drawing), and the chunked LOD kind (draw calls, triangles,
#     frame time); then VIPM's quality there with --source over the first QFRAMES frames (error,
#     pops, holes, image pops; default 300).
#
#  4. Levels above the roots (`build --upper-levels auto`): the 8193² synth's low pass against
#     the flat forest at a large budget, then within CACHE_SMALL_MB (default 256), and the
#     16385² synth flown within it (resident memory, frames waiting on IO, coarser frames,
#     evictions).
#
#   bench/vipm_far_field.sh [FRAMES] [TAU]     defaults: 2000 2
#
# Scratch files: $BENCH_DIR/vipm_far_field. ONLY="crater zion synth upper" runs just those
# parts (upper builds the 16385² synth: about 4 GB of memory and an hour of CPU).
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
frames=${1:-2000}
tau=${2:-2}
terralod=${TERRALOD:-$here/build/release/apps/terralod/terralod}
dir=${BENCH_DIR:-$here/build/bench}/vipm_far_field
mkdir -p "$dir"
data=$here/tests/data
want() { [ -z "${ONLY:-}" ] || [[ " $ONLY " == *" $1 "* ]]; }

figures() {  # JSON file, then keys: one "key=value" per key bench wrote
  python3 - "$@" <<'PY'
import json, sys
j = json.load(open(sys.argv[1]))
print("  ".join(f"{k}={j[k]:.4g}" if isinstance(j.get(k), float) else f"{k}={j.get(k)}"
                for k in sys.argv[2:]))
PY
}

for entry in "crater|crater_lake_0513.bt" "zion|zion_srtm3_utm12_30m.tif"; do
  IFS='|' read -r name file <<<"$entry"
  want "$name" || continue
  [ -e "$dir/$name.tlod" ] ||
    "$terralod" build "$data/$file" --kind vipm -o "$dir/$name.tlod" >/dev/null
  flight=(--auto-flight --tau "$tau" --size 320x240)
  echo "## $name"
  for run in "climb|--climb-only" "pass|--frames $frames" "pass_noskirts|--frames $frames --no-skirts"; do
    IFS='|' read -r what opts <<<"$run"
    # shellcheck disable=SC2086
    "$terralod" bench "$dir/$name.tlod" "${flight[@]}" $opts --stitch fans \
      --source "$data/$file" --json "$dir/${name}_fans_$what.json" >/dev/null
    echo "fans, $what: $(figures "$dir/${name}_fans_$what.json" max_error_px max_pop_px \
      holes_total image_pop_mean material_pop_px blot_switch_mean_max blots_p50 \
      triangles_p50 fan_change_ms_p50 fan_change_ms_p99 fan_change_ms_max fan_frame_ms_p50)"
  done
  for run in "flanges|--stitch flanges" "fans|--stitch fans" "noblots|--no-blots" "blots|"; do
    IFS='|' read -r what opts <<<"$run"
    # shellcheck disable=SC2086
    "$terralod" bench "$dir/$name.tlod" "${flight[@]}" --frames "$frames" $opts \
      --json "$dir/${name}_time_$what.json" >/dev/null
    echo "timing, $what: $(figures "$dir/${name}_time_$what.json" frame_ms_p50 frame_ms_p99 \
      triangles_p50 draws_p50 blots_p50 fan_change_ms_p50 fan_change_ms_p99 fan_change_ms_max \
      fan_frame_ms_p50)"
  done
done

if want synth; then
  [ -e "$dir/s8193.tif" ] || "$terralod" synth --size 8193 -o "$dir/s8193.tif" >/dev/null
  [ -e "$dir/s8193_vipm.tlod" ] ||
    "$terralod" build "$dir/s8193.tif" --kind vipm --upper-levels 0 \
      -o "$dir/s8193_vipm.tlod" >/dev/null
  [ -e "$dir/s8193_static.tlod" ] ||
    "$terralod" build "$dir/s8193.tif" --no-texture -o "$dir/s8193_static.tlod" >/dev/null
  # Every root stays resident (about 1.3 GB here, over the default 512 MB budget: leaves would
  # never load), so the budget is raised until streaming keeps only fallbacks resident. The
  # flights start with the first view loaded (--warm-start), so they measure streaming from
  # there rather than the thousands of leaves the first frame wants arriving.
  flight=(--auto-flight --tau "$tau" --size 1024x768 --frames "$frames" --warm-start
    --cache-mb "${CACHE_MB:-4096}")
  echo "## 8193² synth, 1024×768"
  for run in "vipm_super|s8193_vipm|--stitch fans" "vipm_flanges|s8193_vipm|--stitch flanges" \
    "vipm_nosuper|s8193_vipm|--stitch fans --no-super-chunks" \
    "vipm_perchunk|s8193_vipm|--stitch fans --no-blots --no-super-chunks" "static|s8193_static|"; do
    IFS='|' read -r what tileset opts <<<"$run"
    # shellcheck disable=SC2086
    "$terralod" bench "$dir/$tileset.tlod" "${flight[@]}" $opts \
      --json "$dir/synth_$what.json" >/dev/null
    echo "$what: $(figures "$dir/synth_$what.json" frame_ms_p50 frame_ms_p99 triangles_p50 \
      draws_p50 blots_p50 super_chunk_calls_p50 fan_frame_ms_p50 coarser_than_wanted_frames)"
  done
  for stitch in fans flanges; do
    "$terralod" bench "$dir/s8193_vipm.tlod" --auto-flight --tau "$tau" --size 1024x768 \
      --frames "${QFRAMES:-300}" --stitch "$stitch" --source "$dir/s8193.tif" \
      --cache-mb "${CACHE_MB:-4096}" --warm-start \
      --json "$dir/synth_quality_$stitch.json" >/dev/null
    echo "quality, $stitch: $(figures "$dir/synth_quality_$stitch.json" max_error_px max_pop_px \
      holes_total image_pop_mean blot_switch_mean_max draws_p50 super_chunk_calls_p50 \
      coarser_than_wanted_frames easing_frames frames_waiting_on_io warm_start_ms)"
  done
fi

if want upper; then
  small=${CACHE_SMALL_MB:-256}
  [ -e "$dir/s8193.tif" ] || "$terralod" synth --size 8193 -o "$dir/s8193.tif" >/dev/null
  [ -e "$dir/s8193_vipm.tlod" ] ||
    "$terralod" build "$dir/s8193.tif" --kind vipm --upper-levels 0 \
      -o "$dir/s8193_vipm.tlod" >/dev/null
  [ -e "$dir/s8193_up.tlod" ] || "$terralod" build "$dir/s8193.tif" --kind vipm \
    --upper-levels auto -o "$dir/s8193_up.tlod" >/dev/null
  [ -e "$dir/s16385.tif" ] || "$terralod" synth --size 16385 -o "$dir/s16385.tif" >/dev/null
  [ -e "$dir/s16385_up.tlod" ] || "$terralod" build "$dir/s16385.tif" --kind vipm \
    --upper-levels auto -o "$dir/s16385_up.tlod" >/dev/null
  echo "## Levels above the roots, 1024×768"
  for run in "flat_large|s8193_vipm|${CACHE_MB:-4096}" "up_large|s8193_up|${CACHE_MB:-4096}" \
    "up_small|s8193_up|$small" "up16385_small|s16385_up|$small"; do
    IFS='|' read -r what tileset cache <<<"$run"
    "$terralod" bench "$dir/$tileset.tlod" --auto-flight --tau "$tau" --size 1024x768 \
      --frames "$frames" --stitch fans --cache-mb "$cache" --json "$dir/upper_$what.json" >/dev/null
    echo "$what: $(figures "$dir/upper_$what.json" frame_ms_p50 triangles_p50 draws_p50 \
      resident_mb_max frames_waiting_on_io coarser_than_wanted_frames evictions loads)"
  done
fi
