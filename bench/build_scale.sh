#!/usr/bin/env bash
# Whole-process build benchmark: synthesise a SIZE x SIZE DEM, build it with 1 and 2 threads,
# and print one Markdown table row per run (wall time, peak RSS, output size and mesh figures).
#
#   bench/build_scale.sh SIZE [SPACING_M] [MAX_ERROR_M] [THREADS...]
#   e.g. bench/build_scale.sh 8193            # the standard 8193^2 benchmark, 1 and 2 threads
#        bench/build_scale.sh 65537 1 1 2     # the scale benchmark, 2 threads only
#
# Needs a release build (make build) and GNU time (/usr/bin/time). Scratch files go to
# $BENCH_DIR (default build/bench), which must have room for the DEM (about 1.6 bytes/sample).
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
size=${1:?usage: build_scale.sh SIZE [SPACING_M] [MAX_ERROR_M] [THREADS...]}
spacing=${2:-1}
max_error=${3:-1}
shift $(( $# < 3 ? $# : 3 ))
threads=("$@")
[ ${#threads[@]} -gt 0 ] || threads=(1 2)
terralod=${TERRALOD:-$here/build/release/apps/terralod/terralod}
dir=${BENCH_DIR:-$here/build/bench}
mkdir -p "$dir"
dem="$dir/synth_${size}_${spacing}m.tif"

if [ ! -f "$dem" ]; then
  /usr/bin/time -f "%e %M" -o "$dir/synth.time" \
    "$terralod" synth --size "$size" --spacing "$spacing" -o "$dem" >/dev/null
  read -r wall rss <"$dir/synth.time"
  echo "synth ${size}^2 at ${spacing} m: ${wall} s, peak RSS $((rss / 1024)) MB, $(( $(stat -c %s "$dem") / 1000000 )) MB on disk" >&2
fi

echo "| input | threads | wall s | peak RSS MB | output MB | triangles | vertices | bytes/vertex | bytes/sample | M samples/s |"
echo "|---|---|---|---|---|---|---|---|---|---|"
for t in "${threads[@]}"; do
  out="$dir/synth_${size}_${spacing}m_t${t}.tlod"
  /usr/bin/time -f "%e %M" -o "$dir/build.time" \
    "$terralod" build "$dem" -o "$out" --max-error "$max_error" --threads "$t" >/dev/null
  read -r wall rss <"$dir/build.time"
  "$terralod" info "$out" --json >"$dir/info.json"
  python3 - "$dir/info.json" "$size" "$spacing" "$t" "$wall" "$rss" <<'PY'
import json, sys
info = json.load(open(sys.argv[1]))
size, spacing, threads, wall, rss = sys.argv[2], sys.argv[3], sys.argv[4], float(sys.argv[5]), int(sys.argv[6])
samples = info["source_size"][0] * info["source_size"][1]
print(f"| synth {size}² at {spacing} m | {threads} | {wall:.2f} | {rss / 1024:.0f} | "
      f"{info['file_bytes'] / 1e6:.2f} | {info['triangles']:,} | {info['vertices']:,} | "
      f"{info['file_bytes'] / info['vertices']:.2f} | {info['file_bytes'] / samples:.3f} | "
      f"{samples / wall / 1e6:.1f} |")
PY
  rm -f "$out"
done
