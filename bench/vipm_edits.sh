#!/usr/bin/env bash
# `terralod edit` on the 8193² synth (1 m cells, 16,384 leaves): one raise stroke covering 1, 4
# and 16 leaves (and their roots), REPS times each on a fresh copy of the tileset; then the
# last stroke once with --rebuild-all (every chunk built again: minutes) and a check that both
# give the same bytes. Prints each edit's own summary line: total time, the source read, the chunks.
#
#   bench/vipm_edits.sh [REPS]     default 3
#
# Scratch files: $BENCH_DIR/vipm_edits (the synth and its tileset are kept between runs).
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
reps=${1:-3}
terralod=${TERRALOD:-$here/build/release/apps/terralod/terralod}
dir=${BENCH_DIR:-$here/build/bench}/vipm_edits
mkdir -p "$dir"
cd "$dir"
[ -e s8193.tif ] || "$terralod" synth --size 8193 -o s8193.tif >/dev/null
[ -e s8193.tlod ] || "$terralod" build s8193.tif --kind vipm -o s8193.tlod >/dev/null

# Centre and radius (metres, 1 m cells, 64-cell leaves): inside one leaf; on a corner shared
# by four; over the middle of a 4 x 4 block of leaves (its corner at 4096, 4096).
for stroke in "1|4000,4000|20" "4|4096,4096|40" "16|4096,4096|100"; do
  IFS='|' read -r leaves center radius <<<"$stroke"
  printf '{"edits": [{"brush": "raise", "center": [%s], "radius": %s, "amount": 5}]}\n' \
    "$center" "$radius" >"stroke$leaves.json"
  echo "## a stroke over $leaves leaves (centre $center, radius $radius m)"
  for ((i = 0; i < reps; ++i)); do
    cp s8193.tlod edited.tlod
    "$terralod" edit edited.tlod --script "stroke$leaves.json"
  done
done
echo "## the last stroke with --rebuild-all"
cp s8193.tlod all.tlod
"$terralod" edit all.tlod --script stroke16.json --rebuild-all
cmp -s edited.tlod all.tlod && echo "same bytes as --rebuild-all" ||
  { echo "DIFFERENT bytes from --rebuild-all" && exit 1; }
