#!/usr/bin/env bash
# scripts/cesium-screenshot.sh DIR --eye X,Y,Z --target X,Y,Z [--size WxH] [--fov DEG]
#     [--tau T] [--background RRGGBB] [--stats FILE.json] [--timeout S] -o OUT.png
#
# A picture of a 3D Tiles export (`terralod export TILESET --format 3dtiles -o DIR`) as CesiumJS
# draws it, from the camera `terralod render --eye --target --size --fov --tau` would use:
#   1. `terralod where DIR` turns the camera (the tileset's local metres) into Earth-centred
#      coordinates through the placement the export used;
#   2. nginx (Debian's) serves DIR, CesiumJS (npm `cesium`, pinned in tests/tools) and a small
#      page (scripts/cesium/screenshot.html) on 127.0.0.1 at a free port;
#   3. headless Chromium (Debian's) opens the page with software WebGL (SwiftShader), which
#      shows only the tileset (no globe, imagery, sky, sun, fog or anti-aliasing) at CesiumJS's
#      maximumScreenSpaceError = tau, waits until CesiumJS reports every tile the view needs
#      loaded, and sends the picture back to nginx (HTTP PUT);
#   4. the picture is written to OUT.png (OUT.jpg or OUT.jpeg: JPEG, quality 90), and the
#      figures (tiles requested, tiles drawn, load time) are printed as a JSON line (and
#      written to --stats FILE).
# The background defaults to terralod render's sky colour (9cc3e6). Everything runs in a
# temporary directory removed on exit. Needs `make` (or scripts/install-deps.sh and a build)
# first. TERRALOD overrides the terralod binary. Software WebGL on every machine, so that the
# same export and camera give the same picture.
set -euo pipefail

here=$(cd "$(dirname "$0")/.." && pwd)
usage() {
  sed -n '2,3p' "$0" | sed 's/^# //' >&2
  exit 2
}
die() {
  echo "cesium-screenshot: error: $*" >&2
  exit 1
}

dir="" eye="" target="" size="1024x768" fov="60" tau="2" background="9cc3e6" out="" stats=""
timeout_s=180
while [ $# -gt 0 ]; do
  case "$1" in
    --eye) eye=${2:-}; shift 2 ;;
    --target) target=${2:-}; shift 2 ;;
    --size) size=${2:-}; shift 2 ;;
    --fov) fov=${2:-}; shift 2 ;;
    --tau) tau=${2:-}; shift 2 ;;
    --background) background=${2:-}; shift 2 ;;
    --stats) stats=${2:-}; shift 2 ;;
    --timeout) timeout_s=${2:-}; shift 2 ;;
    -o|--output) out=${2:-}; shift 2 ;;
    -h|--help) usage ;;
    -*) die "unknown option $1" ;;
    *) [ -z "$dir" ] || die "one export directory, not '$dir' and '$1'"; dir=$1; shift ;;
  esac
done
[ -n "$dir" ] && [ -n "$eye" ] && [ -n "$target" ] && [ -n "$out" ] || usage
[ -f "$dir/tileset.json" ] || die "$dir: no tileset.json (not a 3D Tiles export)"
[[ "$size" =~ ^([1-9][0-9]{0,4})x([1-9][0-9]{0,4})$ ]] || die "--size must be WxH, not '$size'"
width=${BASH_REMATCH[1]} height=${BASH_REMATCH[2]}
[[ "$background" =~ ^[0-9a-fA-F]{6}$ ]] || die "--background must be RRGGBB, not '$background'"
[[ "$fov" =~ ^[0-9]+([.][0-9]+)?$ ]] || die "--fov must be a number of degrees, not '$fov'"
[[ "$tau" =~ ^[0-9]+([.][0-9]+)?$ ]] || die "--tau must be a positive number, not '$tau'"
[[ "$timeout_s" =~ ^[1-9][0-9]*$ ]] || die "--timeout must be whole seconds, not '$timeout_s'"

terralod=${TERRALOD:-$here/build/release/apps/terralod/terralod}
cesium="$here/tests/tools/node_modules/cesium/Build/Cesium"
nginx=$(command -v nginx || echo /usr/sbin/nginx)
chromium=$(command -v chromium || command -v chromium-browser || true)
[ -x "$terralod" ] || die "$terralod: no terralod binary (run make, or set TERRALOD)"
[ -f "$cesium/Cesium.js" ] || die "$cesium: no CesiumJS (run scripts/install-deps.sh)"
[ -x "$nginx" ] || die "no nginx (run scripts/install-deps.sh)"
[ -n "$chromium" ] || die "no chromium (run scripts/install-deps.sh)"

# 1. The camera on Earth.
camera=$("$terralod" where "$dir" --eye "$eye" --target "$target") || exit 1
field() { node -e 'const j = JSON.parse(process.argv[1]); console.log([].concat(j[process.argv[2]]).join(","))' "$camera" "$1"; }
eye_ecef=$(field eye_ecef) direction=$(field direction_ecef) up=$(field up_ecef)

# 2. nginx on a free port, the page, CesiumJS and the tiles under one root.
work=$(mktemp -d "${TMPDIR:-/tmp}/cesium-screenshot.XXXXXX")
nginx_pid="" chromium_pid=""
cleanup() {
  [ -z "$chromium_pid" ] || kill -9 -- "-$chromium_pid" 2>/dev/null || kill -9 "$chromium_pid" 2>/dev/null || true
  [ -z "$nginx_pid" ] || kill "$nginx_pid" 2>/dev/null || true
  wait 2>/dev/null || true
  rm -rf "$work"
}
trap cleanup EXIT
trap 'exit 130' INT TERM
mkdir -p "$work/www/out" "$work/temp" "$work/profile"
cp "$here/scripts/cesium/screenshot.html" "$work/www/index.html"
ln -s "$cesium" "$work/www/cesium"
ln -s "$(cd "$dir" && pwd)" "$work/www/tiles"
free_port() {
  node -e 'const s = require("net").createServer(); s.listen(0, "127.0.0.1", () => { console.log(s.address().port); s.close(); });'
}
start_nginx() {
  port=$(free_port)
  cat >"$work/nginx.conf" <<CONF
daemon off;
master_process off;
worker_processes 1;
error_log $work/error.log;
pid $work/nginx.pid;
events { worker_connections 256; }
http {
  types { text/html html; application/javascript js; text/css css; application/json json;
          model/gltf-binary glb; image/png png; image/jpeg jpg; application/octet-stream bin; }
  default_type application/octet-stream;
  access_log $work/access.log;
  client_body_temp_path $work/temp/body; proxy_temp_path $work/temp/proxy;
  fastcgi_temp_path $work/temp/fastcgi; uwsgi_temp_path $work/temp/uwsgi;
  scgi_temp_path $work/temp/scgi;
  client_max_body_size 256m;
  server {
    listen 127.0.0.1:$port;
    root $work/www;
    location /out/ { dav_methods PUT; create_full_put_path on; }
  }
}
CONF
  "$nginx" -c "$work/nginx.conf" -p "$work" 2>>"$work/error.log" &
  nginx_pid=$!
  for _ in $(seq 100); do
    if (exec 3<>"/dev/tcp/127.0.0.1/$port") 2>/dev/null; then return 0; fi
    kill -0 "$nginx_pid" 2>/dev/null || { nginx_pid=""; return 1; }
    sleep 0.1
  done
  return 1
}
started=0
for _ in 1 2 3 4 5; do start_nginx && { started=1; break; }; done
[ "$started" = 1 ] || die "nginx did not start: $(tail -n 1 "$work/error.log" 2>/dev/null)"

# 3. Chromium, headless with software WebGL, until the page has sent its picture.
type=png
case "$out" in *.jpg | *.jpeg | *.JPG | *.JPEG) type=jpeg ;; esac
query="size=$width,$height&fov=$fov&tau=$tau&background=$background&timeout_s=$timeout_s&type=$type"
query+="&eye=$eye_ecef&direction=$direction&up=$up"
setsid "$chromium" --headless=new --no-sandbox --no-first-run --disable-extensions \
  --use-angle=swiftshader --enable-unsafe-swiftshader --ignore-gpu-blocklist \
  --force-device-scale-factor=1 --window-size="$((width + 64)),$((height + 64))" \
  --user-data-dir="$work/profile" "http://127.0.0.1:$port/index.html?$query" \
  >"$work/chromium.log" 2>&1 &
chromium_pid=$!
deadline=$((SECONDS + timeout_s + 30))
while [ ! -s "$work/www/out/done.txt" ] && [ ! -s "$work/www/out/error.txt" ]; do
  [ $SECONDS -lt $deadline ] || die "CesiumJS sent no picture within $((timeout_s + 30)) s"
  kill -0 "$chromium_pid" 2>/dev/null || die "chromium exited: $(tail -n 1 "$work/chromium.log")"
  sleep 0.2
done
[ ! -s "$work/www/out/error.txt" ] || die "the CesiumJS page failed: $(head -n 1 "$work/www/out/error.txt")"
figures=$(cat "$work/www/out/done.txt")
node -e 'const j = JSON.parse(process.argv[1]); if (!j.loaded) process.exit(1)' "$figures" ||
  die "CesiumJS had not loaded every tile after $timeout_s s: $figures"
node -e 'const [w, h] = JSON.parse(process.argv[1]).canvas; if (w != process.argv[2] || h != process.argv[3]) process.exit(1)' \
  "$figures" "$width" "$height" || die "the canvas is not ${width}x${height}: $figures"

# 4. The picture and the figures.
mkdir -p "$(dirname "$out")"
cat "$work/www/out/shot" >"$out.partial" && mv "$out.partial" "$out"  # (cat: the umask's mode, not nginx's 0600)
[ -z "$stats" ] || printf '%s\n' "$figures" >"$stats"
printf '%s\n' "$figures"
