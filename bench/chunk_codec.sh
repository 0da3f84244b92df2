#!/usr/bin/env bash
# RTIN chunks stored as their bintree (the default, format version 7) against meshoptimizer's
# streams (--chunk-codec meshopt): file and geometry bytes, bytes per source sample, build wall
# (medians of RUNS rounds, the two builds in turn in each, so drift hits them alike), and
# `verify --source` on each (it decodes every chunk and its parent: where decoding shows; same
# pairing), whose verdict on the bintree tileset ends the report.
# docs/benchmarks.md "RTIN chunks stored as their bintree" has the figures.
#
#   bench/chunk_codec.sh DEM [RUNS] [terralod build options...]
#   e.g. bench/chunk_codec.sh tests/data/crater_lake_0513.bt 3 --no-texture --max-error 1
set -euo pipefail
cd "$(dirname "$0")/.."
terralod=${TERRALOD:-build/release/apps/terralod/terralod}
dem=$1
runs=${2:-3}
shift $(($# < 2 ? $# : 2))
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

python3 - "$terralod" "$dem" "$runs" "$work" "$@" <<'PY'
import json, os, statistics, subprocess, sys, time
terralod, dem, runs, work, extra = sys.argv[1], sys.argv[2], int(sys.argv[3]), sys.argv[4], sys.argv[5:]
codecs = ["bintree", "meshopt"]
build = {c: [] for c in codecs}
decode = {c: [] for c in codecs}

def timed(args):
    t0 = time.monotonic()
    subprocess.run(args, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    return time.monotonic() - t0

for r in range(runs):
    for c in codecs:
        build[c].append(timed([terralod, "build", dem, "-o", f"{work}/{c}.tlod",
                               "--chunk-codec", c, *extra]))
    for c in codecs:
        decode[c].append(timed([terralod, "verify", f"{work}/{c}.tlod", "--source", dem]))
    print(f"round {r + 1} of {runs}", file=sys.stderr)

def info(c):
    out = subprocess.run([terralod, "info", f"{work}/{c}.tlod", "--json"], check=True,
                         capture_output=True, text=True).stdout
    return json.loads(out)

med = statistics.median
print(f"{dem} {' '.join(extra)}, {runs} rounds:\n")
print("| codec | file bytes | geometry bytes | bytes / sample | build wall s | verify wall s |")
print("|---|---:|---:|---:|---:|---:|")
sizes = {}
for c in codecs:
    i = info(c)
    size = os.path.getsize(f"{work}/{c}.tlod")
    geometry = i["chunk_bytes"]
    samples = i["source_size"][0] * i["source_size"][1]
    sizes[c] = (size, geometry)
    print(f"| {c} | {size:,} | {geometry:,} | {size / samples:.3f} | {med(build[c]):.3f} | "
          f"{med(decode[c]):.3f} |")
pair = lambda d: med([a / b for a, b in zip(d["bintree"], d["meshopt"])])
print(f"\nbintree / meshopt: file {sizes['bintree'][0] / sizes['meshopt'][0]:.3f}, geometry "
      f"{sizes['bintree'][1] / sizes['meshopt'][1]:.3f}, paired build wall {pair(build):.3f}, "
      f"paired verify wall {pair(decode):.3f}")
PY
echo
"$terralod" verify "$work/bintree.tlod" --source "$dem" | tail -1
