#!/usr/bin/env bash
# Installs every Debian package terralod needs to build, test and run.
# Idempotent: packages already present are skipped, so a second run is quick.
# Works as root or through sudo. With --demo, only what building and running terralod needs.
set -euo pipefail

# What `terralod` itself needs to build and run (make demo installs only these: --demo).
demo_packages=(
  # toolchain
  build-essential cmake ninja-build pkg-config
  # rasters, meshes, compression
  libgdal-dev libmeshoptimizer-dev libzstd-dev zlib1g-dev
  # the allocator: jemalloc, with transparent huge pages (apps/terralod/allocator.cpp)
  libjemalloc-dev
  # ray casting for the vegetation baker (terralod vegetation bake)
  libembree-dev
  # math, CLI, JSON, images
  libglm-dev libcli11-dev nlohmann-json3-dev libstb-dev
  # OpenGL 4.5 core through EGL (headless) and GLFW (windows), Dear ImGui
  libepoxy-dev libegl-dev libgl-dev libglfw3-dev libimgui-dev libgl1-mesa-dri libegl-mesa0
  # network: libcurl for HTTP tilesets
  libcurl4-openssl-dev
)
# What the tests, the benchmarks and the format check need besides (make test, make build).
test_packages=(
  clang-format gdal-bin
  # sanitizer builds and fuzzing: clang, its runtimes (ASan, UBSan, TSan, libFuzzer) and
  # llvm-symbolizer for readable reports
  clang libclang-rt-14-dev llvm
  # OpenMesh: only bench/bench_vipm_openmesh, the VIPM generation benchmark
  libopenmesh-dev
  # a virtual X server for the windowed tests
  xvfb xauth
  # nginx (/usr/sbin/nginx) serves tilesets in the HTTP tests
  nginx
  # a real 3D Tiles client for the export's test: CesiumJS (npm, below) in headless Chromium
  # (scripts/cesium-screenshot.sh)
  chromium
  # a real single-node Slurm cluster for the cluster build's tests (scripts/slurm-local.sh)
  slurm-wlm munge
  # tests and benchmarks; gnuplot draws the plots of `terralod bench --report`
  libgtest-dev libgmock-dev libbenchmark-dev gnuplot-nox
)
demo_only=false
case "${1:-}" in
  --demo) demo_only=true ;;
  "") ;;
  *) echo "install-deps: unknown argument '$1' (usage: install-deps.sh [--demo])" >&2; exit 2 ;;
esac
packages=("${demo_packages[@]}")
if ! $demo_only; then
  packages+=("${test_packages[@]}")
  # The glTF validator test runs on node; the machine image may already ship node and npm
  # outside Debian's packages, in which case Debian's npm would conflict with it.
  command -v npm >/dev/null 2>&1 || packages+=(nodejs npm)
fi

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done

if [ ${#missing[@]} -gt 0 ]; then
  if [ "$(id -u)" -eq 0 ]; then sudo=""; else sudo="sudo"; fi
  echo "install-deps: installing ${missing[*]}"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
  # Debian starts the nginx service (port 80) on installation; the tests run their own nginx
  # on a free port. If we just installed it, stop that service again (and keep it from starting
  # at boot); an nginx the machine already had is left alone.
  if [[ " ${missing[*]} " == *" nginx "* ]]; then
    if command -v systemctl >/dev/null 2>&1 && [ -d /run/systemd/system ]; then
      $sudo systemctl disable --now nginx >/dev/null 2>&1 || true
    elif command -v service >/dev/null 2>&1; then
      $sudo service nginx stop >/dev/null 2>&1 || true
    fi
  fi
fi

if $demo_only; then
  echo "install-deps: the demo's dependencies present"
  exit 0
fi

# npm packages the tests and benchmarks run, pinned by tests/tools/package-lock.json: the Khronos
# glTF validator (the export tests), CesiumJS (scripts/cesium-screenshot.sh), and delatin and
# @mapbox/martini (bench/triangles_per_error.sh's yardsticks).
here=$(cd "$(dirname "$0")/.." && pwd)
modules=$here/tests/tools/node_modules
if [ -f "$here/tests/tools/package.json" ] && { [ ! -d "$modules/gltf-validator" ] ||
  [ ! -f "$modules/cesium/package.json" ] || [ ! -f "$modules/delatin/package.json" ] ||
  [ ! -f "$modules/@mapbox/martini/package.json" ]; }; then
  (cd "$here/tests/tools" && npm ci --silent --no-audit --no-fund >/dev/null)
fi
echo "install-deps: all dependencies present"
