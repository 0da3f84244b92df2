#!/usr/bin/env bash
# Issue 7's leak check: a full run — synth, build (with a draped image), info, verify, render
# (an overview and flight frames), bench (with --source), export — with the `asan` preset's
# CLI (AddressSanitizer, UBSan, LeakSanitizer). Every command must exit 0 with no report.
# No suppressions: the GL driver libraries are kept loaded until exit (bench/
# keep_libraries_loaded.c, LD_PRELOADed), so memory Mesa's driver still holds in its globals is
# not mistaken for a leak after libEGL_mesa unloads it (docs/reliability.md). Scratch files:
# $BENCH_DIR/leaks.
#
#   bench/leak_check.sh     (build first: cmake --preset asan && cmake --build --preset asan-cli)
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
terralod=${TERRALOD:-$here/build/asan/apps/terralod/terralod}
dir=${BENCH_DIR:-$here/build/bench}/leaks
data=$here/tests/data
[ -x "$terralod" ] || { echo "leak_check.sh: build first: cmake --preset asan && cmake --build --preset asan-cli" >&2; exit 1; }
rm -rf "$dir"
mkdir -p "$dir/flight"
export ASAN_OPTIONS=detect_leaks=1:halt_on_error=1:strict_string_checks=1
cc -shared -fPIC -o "$dir/keep_libraries_loaded.so" "$here/bench/keep_libraries_loaded.c"
export LD_PRELOAD=$dir/keep_libraries_loaded.so
export UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1
log=$dir/log.txt
: >"$log"
run() {
  echo "leak_check.sh: terralod $*" | tee -a "$log"
  "$terralod" "$@" >>"$log" 2>&1 || { echo "leak_check.sh: FAILED (see $log)" >&2; exit 1; }
}
run synth --size 257 -o "$dir/synth.tif"
run build "$dir/synth.tif" -o "$dir/synth.tlod"
run build "$data/zion_srtm3_utm12_30m.tif" --texture "$data/zion_landsat8_rgb_utm12_30m.tif" \
  -o "$dir/zion.tlod"
run info "$dir/zion.tlod" --json
run verify "$dir/zion.tlod" --source "$data/zion_srtm3_utm12_30m.tif"
run render "$dir/zion.tlod" -o "$dir/zion.png" --size 640x480
run render "$dir/zion.tlod" --auto-flight --climb-only --frames 60 --every 20 --size 320x240 \
  --frames-dir "$dir/flight"
run bench "$dir/zion.tlod" --auto-flight --frames 120 --size 320x240 --cache-mb 16 \
  --source "$data/zion_srtm3_utm12_30m.tif" --json "$dir/bench.json"
run bench "$dir/synth.tlod" --auto-flight --frames 60 --size 320x240 --no-textures \
  --json "$dir/bench_synth.json"
run export "$dir/synth.tlod" -o "$dir/synth.glb"
echo "leak_check.sh: clean: every command exited 0 with no LeakSanitizer, ASan or UBSan report (log: $log)"
