#!/usr/bin/env bash
# Issue 5's streaming benchmark: a 32769² synth (about 1 G samples) with textures, flown along
# the automatic flight's low pass (the first FRAMES frames, about 30 km at the flight's
# 0.5 %-of-height steps) under --cache-mb CACHE_MB, read from the local file and then served by
# nginx on 127.0.0.1. Scratch in $BENCH_DIR/stream.
#
#   bench/streaming.sh timing  [FRAMES] [CACHE_MB]   frame times as an application sees them
#                                                     (no quality metrics between frames); run
#                                                     it on a quiet machine
#   bench/streaming.sh quality [FRAMES] [CACHE_MB]   error, pops and holes against the source
#                                                     (every METRIC_STRIDE-th sample, default 32)
#   defaults: 6800 256
#
# Each run writes $dir/<mode>_<local|http>.json and a report ($dir/<mode>_<local|http>/report.md),
# then prints a table of both.
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
mode=${1:?usage: bench/streaming.sh timing|quality [FRAMES] [CACHE_MB]}
frames=${2:-6800}
cache=${3:-256}
stride=${METRIC_STRIDE:-32}
terralod=${TERRALOD:-$here/build/release/apps/terralod/terralod}
dir=${BENCH_DIR:-$here/build/bench}/stream
mkdir -p "$dir"
[ -f "$dir/synth_32769.tif" ] || "$terralod" synth --size 32769 -o "$dir/synth_32769.tif"
[ -f "$dir/synth_32769.tlod" ] ||
  /usr/bin/time -v "$terralod" build "$dir/synth_32769.tif" -o "$dir/synth_32769.tlod" 2> "$dir/build_time.txt"
case $mode in
  timing) extra=() ;;
  quality) extra=(--source "$dir/synth_32769.tif" --metric-stride "$stride") ;;
  *) echo "bench/streaming.sh: mode must be timing or quality" >&2; exit 1 ;;
esac
run() {
  "$terralod" bench "$1" --auto-flight --frames "$frames" --cache-mb "$cache" "${extra[@]}" \
    --json "$dir/${mode}_$2.json" --report "$dir/${mode}_$2"
}
run "$dir/synth_32769.tlod" local
# nginx on a free port, serving $dir.
port=$(python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1",0)); print(s.getsockname()[1])')
conf=$dir/nginx.conf
cat > "$conf" <<CONF
worker_processes 1; master_process off; daemon off; pid $dir/nginx.pid; error_log $dir/nginx_error.log;
events {}
http { access_log off; client_body_temp_path $dir; proxy_temp_path $dir; fastcgi_temp_path $dir;
       uwsgi_temp_path $dir; scgi_temp_path $dir;
       server { listen 127.0.0.1:$port; root $dir; } }
CONF
/usr/sbin/nginx -p "$dir" -c "$conf" & nginx=$!
trap 'kill $nginx 2>/dev/null || true' EXIT
sleep 1
run "http://127.0.0.1:$port/synth_32769.tlod" http
python3 - "$dir" "$mode" <<'PY'
import json, sys
d, mode = sys.argv[1:]
keys = ["frames", "resident_mb_max", "holes_total", "frames_waiting_on_io", "max_error_px",
        "max_error_px_all", "coarser_than_wanted_frames", "frame_ms_p50", "frame_ms_p99",
        "bytes_read", "loads", "evictions", "upload_ms_max", "max_pop_px", "image_pop_mean"]
rows = {k: json.load(open(f"{d}/{mode}_{k}.json")) for k in ("local", "http")}
print("| figure | local file | HTTP (nginx, 127.0.0.1) |")
print("|---|---|---|")
for key in keys:
    print(f"| {key} | {rows['local'].get(key, '—')} | {rows['http'].get(key, '—')} |")
PY
