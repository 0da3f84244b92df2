#!/usr/bin/env bash
# `terralod edit` on the 8193² synth (1 m cells, 16,384 leaves): one raise stroke covering 1, 4
# and 16 leaves (and their roots), REPS times each on a fresh copy of the tileset; then the
# last stroke once with --rebuild-all (every chunk built again: minutes) and a check that both
# give the same bytes. Prints each edit's own summary line: total time, the source read, the
# chunks. Then the same stroke sizes while flying (bench --edit-script): the time from a stroke
# to its regenerated chunks drawn.
#
#   bench/vipm_edits.sh [REPS]     default 3
#
# Scratch files: $BENCH_DIR/vipm_edits (the synth and its tileset are kept between runs).
# ONLY="edit" or ONLY="flying" runs just that part.
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
reps=${1:-3}
terralod=${TERRALOD:-$here/build/release/apps/terralod/terralod}
dir=${BENCH_DIR:-$here/build/bench}/vipm_edits
mkdir -p "$dir"
cd "$dir"
[ -e s8193.tif ] || "$terralod" synth --size 8193 -o s8193.tif >/dev/null
[ -e s8193.tlod ] || "$terralod" build s8193.tif --kind vipm -o s8193.tlod >/dev/null

want() { [ -z "${ONLY:-}" ] || [[ " $ONLY " == *" $1 "* ]]; }

# Centre and radius (metres, 1 m cells, 64-cell leaves): inside one leaf; on a corner shared
# by four; over the middle of a 4 x 4 block of leaves (its corner at 4096, 4096).
want edit && for stroke in "1|4000,4000|20" "4|4096,4096|40" "16|4096,4096|100"; do
  IFS='|' read -r leaves center radius <<<"$stroke"
  printf '{"edits": [{"brush": "raise", "center": [%s], "radius": %s, "amount": 5}]}\n' \
    "$center" "$radius" >"stroke$leaves.json"
  echo "## a stroke over $leaves leaves (centre $center, radius $radius m)"
  for ((i = 0; i < reps; ++i)); do
    cp s8193.tlod edited.tlod
    "$terralod" edit edited.tlod --script "stroke$leaves.json"
  done
done
if want edit; then
  echo "## the last stroke with --rebuild-all"
  cp s8193.tlod all.tlod
  "$terralod" edit all.tlod --script stroke16.json --rebuild-all
  cmp -s edited.tlod all.tlod && echo "same bytes as --rebuild-all" ||
    { echo "DIFFERENT bytes from --rebuild-all" && exit 1; }
fi

# While flying: the same strokes, three of each size 128 m apart, applied during a low flight
# over them at 640×480 (bench --edit-script, one every 20 frames, after the one before is
# drawn and made): regeneration on a worker thread, and the time from each stroke to its
# chunks drawn, first as their whole grids (interim), then as their regenerated VIPMs (the
# leaves and roots; the nodes above them are made after, edit_upper_*). The flight passes a
# few hundred metres over the strokes, so that their leaves are drawn (the automatic flight's
# low pass is kilometres away from the middle of the map, where only upper nodes are drawn).
cat >over_strokes.json <<'JSON'
{"fov_deg": 60, "size": [640, 480], "frames": 200, "keyframes": [
  {"eye": [3950, 3400, 1250], "target": [4000, 4000, 910]},
  {"eye": [4150, 3900, 1100], "target": [4150, 4400, 910]}]}
JSON
want flying && for leaves in 1 4 16; do
  python3 - "$leaves" >"flying$leaves.json" <<'PY'
import json, sys
leaves = int(sys.argv[1])
# Centres around the middle of the map, under the flight; radii as above.
radius = {1: 20, 4: 40, 16: 100}[leaves]
centre = {1: [4000, 4000], 4: [4096, 4096], 16: [4096, 4096]}[leaves]
edits = [{"brush": "raise" if k % 2 == 0 else "lower",
          "center": [centre[0] + 128 * (k - 1), centre[1] + 128 * (k - 1)],
          "radius": radius, "amount": 5} for k in range(3)]
print(json.dumps({"edits": edits}))
PY
  "$terralod" bench s8193.tlod --flight over_strokes.json --cache-mb 4096 \
    --edit-script "flying$leaves.json" --edit-every 20 --edit-source s8193.tif \
    --json "flying$leaves.out.json" >/dev/null
  python3 - "flying$leaves.out.json" "$leaves" <<'PY'
import json, sys
j = json.load(open(sys.argv[1]))
keys = ["edit_strokes", "edit_swapped", "edit_nodes_p50", "edit_resident_nodes_max",
        "edit_regen_ms_p50", "edit_regen_ms_max", "edit_latency_ms_p50", "edit_latency_ms_max",
        "edit_upper_strokes", "edit_upper_ms_p50", "edit_upper_ms_max", "edit_upper_nodes_p50",
        "edit_latency_frames_p50", "edit_latency_frames_max", "edit_interim_drawn",
        "edit_interim_latency_ms_p50", "edit_interim_latency_ms_max",
        "edit_interim_latency_frames_p50", "edit_interim_latency_frames_max", "frame_ms_p50",
        "frame_ms_max", "frames_waiting_on_io"]
print(f"flying, strokes over {sys.argv[2]} leaves: " +
      "  ".join(f"{k}={j[k]:.4g}" if isinstance(j[k], float) else f"{k}={j[k]}" for k in keys))
PY
done
