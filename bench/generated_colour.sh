#!/usr/bin/env bash
# The generated colour made by the shader (the default: a shade layer, format version 6)
# against the colour baked into the texture (--bake-colour, version 5) and the geometry alone
# (--no-texture): file and texture bytes, build wall and CPU seconds (medians of RUNS rounds,
# the three builds in turn in each, so drift hits them alike), and the frame time of the same
# flight over both textured tilesets. docs/benchmarks.md "The generated colour in the shader"
# has the figures.
#
#   bench/generated_colour.sh DEM [RUNS] [terralod build options...]
#   e.g. bench/generated_colour.sh tests/data/zion_srtm3_utm12_30m.tif 5
set -euo pipefail
cd "$(dirname "$0")/.."
terralod=${TERRALOD:-build/release/apps/terralod/terralod}
dem=$1
runs=${2:-5}
shift $(($# < 2 ? $# : 2))
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

python3 - "$terralod" "$dem" "$runs" "$work" "$@" <<'PY'
import json, os, resource, statistics, subprocess, sys, time
terralod, dem, runs, work, extra = sys.argv[1], sys.argv[2], int(sys.argv[3]), sys.argv[4], sys.argv[5:]
builds = {"shade": [], "baked": ["--bake-colour"], "geometry": ["--no-texture"]}
wall = {k: [] for k in builds}
cpu = {k: [] for k in builds}
for r in range(runs):
    for name, flags in builds.items():
        before = resource.getrusage(resource.RUSAGE_CHILDREN)
        t0 = time.monotonic()
        subprocess.run([terralod, "build", dem, "-o", f"{work}/{name}.tlod", *flags, *extra],
                       check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        wall[name].append(time.monotonic() - t0)
        after = resource.getrusage(resource.RUSAGE_CHILDREN)
        cpu[name].append(after.ru_utime - before.ru_utime + after.ru_stime - before.ru_stime)
    print(f"round {r + 1} of {runs}", file=sys.stderr)

def info(name):
    out = subprocess.run([terralod, "info", f"{work}/{name}.tlod", "--json"], check=True,
                         capture_output=True, text=True).stdout
    return json.loads(out)

def flight(name):
    out = f"{work}/{name}.json"
    subprocess.run([terralod, "bench", f"{work}/{name}.tlod", "--auto-flight", "--climb-only",
                    "--frames", "300", "--size", "640x480", "--json", out], check=True,
                   stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    return json.load(open(out))

med = lambda v: statistics.median(v)
print(f"{dem}, {runs} rounds:\n")
print("| build | file bytes | texture bytes | wall s | CPU s | wall / geometry | CPU / geometry |")
print("|---|---:|---:|---:|---:|---:|---:|")
for name in builds:
    i = info(name)
    size = os.path.getsize(f"{work}/{name}.tlod")
    tex = sum(l.get("texture_bytes", 0) for l in i["per_level"])
    print(f"| {name} | {size:,} | {tex:,} | {med(wall[name]):.3f} | {med(cpu[name]):.3f} | "
          f"{med(wall[name]) / med(wall['geometry']):.2f} | {med(cpu[name]) / med(cpu['geometry']):.2f} |")
ratio = [a / b for a, b in zip(wall["shade"], wall["baked"])]
print(f"\nshade / baked, paired wall: median {med(ratio):.3f} (min {min(ratio):.3f}, max {max(ratio):.3f})")
shade, baked = flight("shade"), flight("baked")
print("\n| flight (climb, 300 frames, 640x480) | shade | baked |\n|---|---:|---:|")
for key in ("frame_ms_p50", "frame_ms_p99", "triangles_p50", "image_pop_mean", "max_texel_per_px"):
    if key in shade and key in baked:
        print(f"| {key} | {shade[key]:.4g} | {baked[key]:.4g} |")
PY
