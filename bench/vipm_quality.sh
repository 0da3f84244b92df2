#!/usr/bin/env bash
# The VIPM kind's quality figures on the issue-20 flights: each DEM built as a VIPM tileset
# (and as a static one, --no-texture, for the triangle counts) and flown with
# `terralod bench --source` on the automatic flight at τ 2:
#  - its whole climb, with geomorphing and with --no-morph;
#  - the first FRAMES frames of its low pass, with geomorphing;
#  - the same climb and pass on the static tileset, without --source (triangles only).
# One Markdown row per tileset: error, pops (and the geomorph's per-frame step), holes, and
# the triangles per frame against the static kind's (p50 and max, climb and pass).
# material_pop_px is printed when bench reports it.
#
#   bench/vipm_quality.sh [FRAMES] [TAU] [SIZE]     defaults: 2000 2 320x240
#
# Scratch files: $BENCH_DIR/vipm_quality. ONLY="name ..." runs just those rows; VIPM_OPTS adds
# bench options to the VIPM runs (e.g. VIPM_OPTS="--stitch fans").
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
frames=${1:-2000}
tau=${2:-2}
size=${3:-320x240}
terralod=${TERRALOD:-$here/build/release/apps/terralod/terralod}
dir=${BENCH_DIR:-$here/build/bench}/vipm_quality
mkdir -p "$dir"
data=$here/tests/data

# name|DEM|VIPM build options
rows=(
  "crater|crater_lake_0513.bt|"
  "zion|zion_srtm3_utm12_30m.tif|"
  "zion_landcover|zion_srtm3_utm12_30m.tif|--materials $data/zion_landcover_classes.tif --palette $data/zion_landcover_palette.json"
)
echo "| tileset | climb frames | max_error_px | max_pop_px | max_morph_step_px | holes | max_pop_px --no-morph | material_pop_px | pass frames | pass max_error_px | pass max_pop_px | pass holes | triangles p50 / max climb, VIPM / static | triangles p50 / max pass, VIPM / static |"
echo "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"
for entry in "${rows[@]}"; do
  IFS='|' read -r name file opts <<<"$entry"
  if [ -n "${ONLY:-}" ] && [[ " $ONLY " != *" $name "* ]]; then continue; fi
  # shellcheck disable=SC2086
  "$terralod" build "$data/$file" --kind vipm $opts -o "$dir/$name.tlod" >/dev/null
  [ -e "$dir/${file%%.*}_static.tlod" ] ||
    "$terralod" build "$data/$file" --no-texture -o "$dir/${file%%.*}_static.tlod" >/dev/null
  run() {
    # shellcheck disable=SC2086
    "$terralod" bench "$dir/$name.tlod" --auto-flight --tau "$tau" --size "$size" \
      --source "$data/$file" --json "$dir/$name$1.json" "${@:2}" ${VIPM_OPTS:-} >/dev/null
  }
  static() {
    "$terralod" bench "$dir/${file%%.*}_static.tlod" --auto-flight --tau "$tau" --size "$size" \
      --json "$dir/$name$1.json" "${@:2}" >/dev/null
  }
  run "_climb" --climb-only && run "_climb_nomorph" --climb-only --no-morph &&
    run "_pass" --frames "$frames" && static "_static_climb" --climb-only &&
    static "_static_pass" --frames "$frames"
  python3 - "$dir" "$name" <<'PY'
import json, sys
d, name = sys.argv[1:]
climb, nomorph, low, sclimb, slow = (
    json.load(open(f"{d}/{name}{k}.json"))
    for k in ("_climb", "_climb_nomorph", "_pass", "_static_climb", "_static_pass"))
def tri(v, s):
    return (f"{v['triangles_p50']:,.0f} / {v['triangles_max']:,.0f} against "
            f"{s['triangles_p50']:,.0f} / {s['triangles_max']:,.0f} "
            f"({v['triangles_p50'] / s['triangles_p50']:.2f}, "
            f"{v['triangles_max'] / s['triangles_max']:.2f})")
material = climb.get("material_pop_px")
print(f"| {name} | {climb['frames']} | {climb['max_error_px']:.3f} | {climb['max_pop_px']:.4f} | "
      f"{climb['max_morph_step_px']:.3f} | {climb['holes_total']} | {nomorph['max_pop_px']:.3f} | "
      f"{'—' if material is None else material} | {low['frames']} | {low['max_error_px']:.3f} | "
      f"{low['max_pop_px']:.4f} | {low['holes_total']} | {tri(climb, sclimb)} | {tri(low, slow)} |")
PY
done
