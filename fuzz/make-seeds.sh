#!/usr/bin/env bash
# Regenerates the seed corpora in fuzz/corpus/<target>/ from the golden tilesets and the
# rasters in tests/data (needs gdal_translate, zstd and python3). The seeds are committed: run this
# only to renew them, and review what changed. Every seed but the flights starts with the
# target's mode byte (see each target's header comment).
set -euo pipefail
cd "$(dirname "$0")/.."
out=fuzz/corpus
golden=tests/data/golden
data=tests/data
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
# fuzz/corpus/vipm_chunk_codec_fuzzer is kept: its seeds are VIPM blobs of Crater Lake windows
# (9 and 17 points square, material rules on and off, --max-error 0.5; stored and as payload)
# made with libs/vipm, until `terralod build --kind vipm` makes a golden VIPM tileset to cut
# them from.
rm -rf "$out"/{tileset_reader,chunk_codec,texture_codec,flight_json,dem_reader}_fuzzer
mkdir -p "$out"/{tileset_reader,chunk_codec,texture_codec,flight_json,dem_reader}_fuzzer

u64() { od -An -t u8 -j "$2" -N 8 "$1" | tr -d ' '; }
u32() { od -An -t u4 -j "$2" -N 4 "$1" | tr -d ' '; }
# withMode MODE FILE OUT: one mode byte, then FILE.
withMode() { { printf "\\x$(printf %02x "$1")"; cat "$2"; } >"$3"; }
# cut FILE OFFSET LENGTH OUT
cut() { dd if="$1" of="$4" bs=64K iflag=skip_bytes,count_bytes skip="$2" count="$3" status=none; }

# Tilesets: the goldens with checksums recomputed by the harness, v1 also as given.
withMode 0 "$golden/v1/gully.tlod" "$out/tileset_reader_fuzzer/v1_gully"
withMode 0 "$golden/v2/gully.tlod" "$out/tileset_reader_fuzzer/v2_gully"
withMode 0 "$golden/v3/gully.tlod" "$out/tileset_reader_fuzzer/v3_gully"
withMode 0 "$golden/v4/gully.tlod" "$out/tileset_reader_fuzzer/v4_gully"
withMode 0 "$golden/v4/gully-untextured.tlod" "$out/tileset_reader_fuzzer/v4_gully_untextured"
withMode 0 "$golden/v7/gully.tlod" "$out/tileset_reader_fuzzer/v7_gully"
withMode 1 "$golden/v1/gully.tlod" "$out/tileset_reader_fuzzer/v1_gully_checksums_kept"
withMode 0 "$golden/vipm/gully.tlod" "$out/tileset_reader_fuzzer/vipm_gully"
# meshKind is a u32 (header offset 24): 0x101 must be refused, not narrowed to kind 1.
cp "$golden/v2/gully.tlod" "$work/kind.tlod"
printf '\x01\x01\x00\x00' | dd of="$work/kind.tlod" bs=1 seek=24 conv=notrunc status=none
withMode 0 "$work/kind.tlod" "$out/tileset_reader_fuzzer/v2_gully_mesh_kind_0x101"

# Chunk blobs (geometry: stored and decompressed) and texture blobs of every node.
for version in v1 v2 v3 vipm; do
  tlod=$golden/$version/gully.tlod
  table=$(u64 "$tlod" $((0x100)))
  count=$(u64 "$tlod" $((0xF8)))
  for ((i = 0; i < count; i++)); do
    node=$((table + i * 64))
    offset=$(u64 "$tlod" $((node + 40)))
    bytes=$(u32 "$tlod" $((node + 48)))
    textureBytes=$(u32 "$tlod" $((node + 60)))
    if [ "$version" = v1 ]; then
      cut "$tlod" "$offset" "$bytes" "$work/blob"
      withMode 0 "$work/blob" "$out/chunk_codec_fuzzer/${version}_node${i}_stored"
      zstd -q -d -c "$work/blob" >"$work/payload"
      withMode 1 "$work/payload" "$out/chunk_codec_fuzzer/${version}_node${i}_payload"
    fi
    if [ "$textureBytes" -gt 0 ]; then
      cut "$tlod" $((offset + bytes)) "$textureBytes" "$work/texture"
      withMode 0 "$work/texture" "$out/texture_codec_fuzzer/${version}_node${i}"
    fi
  done
done

# Version 4 chunk blobs (payload version 2, skirts derived) and version 7's (payload version 3,
# RTIN chunks as their bintree): the node table is a zstd frame of shuffled records
# (docs/format.md "Version 4"), read here with python3.
for version in v4 v7; do
  tlod=$golden/$version/gully.tlod
  [ "$version" = v4 ] && tlod=$golden/v4/gully-untextured.tlod
  python3 - "$tlod" <<'PY' | while read -r i offset bytes; do
import struct, subprocess, sys
data = open(sys.argv[1], "rb").read()
count, table, length = struct.unpack_from("<QQQ", data, 0xF8)
shuffled = subprocess.run(["zstd", "-q", "-d", "-c"], input=data[table:table + length],
                          capture_output=True, check=True).stdout
record = lambda i: bytes(shuffled[k * count + i] for k in range(64))
for i in range(count):
    offset, size = struct.unpack_from("<QI", record(i), 40)
    print(i, offset, size)
PY
    cut "$tlod" "$offset" "$bytes" "$work/blob"
    withMode 0 "$work/blob" "$out/chunk_codec_fuzzer/${version}_node${i}_stored"
    zstd -q -d -c "$work/blob" >"$work/payload"
    withMode 1 "$work/payload" "$out/chunk_codec_fuzzer/${version}_node${i}_payload"
  done
done

# Flights: the README's example, a recorded one, the least a flight needs, and near misses.
f=$out/flight_json_fuzzer
cat >"$f/readme_example.json" <<'JSON'
{"fov_deg": 60, "size": [1024, 768], "frames": 300,
 "keyframes": [{"eye": [100, -200, 900], "target": [500, 400, 300]},
               {"eye": [900, 300, 700], "target": [600, 800, 250]},
               {"eye": [1500, 1400, 1200], "target": [800, 900, 200]}]}
JSON
cat >"$f/recorded.json" <<'JSON'
{
 "fov_deg": 45.5,
 "frames": 4,
 "keyframes": [
  {"eye": [0.0, 0.0, 100.0], "target": [1.0, 1.0, 0.0]},
  {"eye": [10.0, 0.0, 90.0], "target": [11.0, 1.0, 0.0]},
  {"eye": [20.0, 5.0, 80.0], "target": [21.0, 6.0, 0.0]},
  {"eye": [30.0, 10.0, 70.0], "target": [31.0, 11.0, 0.0]}
 ],
 "size": [640, 480]
}
JSON
printf '{"keyframes":[{"eye":[0,0,1],"target":[1,0,0]},{"eye":[5,5,5],"target":[0,0,0]}]}' >"$f/minimal.json"
printf '{"keyframes":[{"eye":[0,0,1],"target":[0,0,1]},{"eye":[1e308,-1e308,0],"target":[0,0,0]}],"frames":1000000}' >"$f/degenerate.json"
printf '{"fov_deg":180,"size":[0,16385],"keyframes":[{"eye":[0,0,1]}],"frames":-1}' >"$f/out_of_range.json"

# Rasters: small crops in the shapes build meets (types, compression, tiling, nodata, scale and
# offset, geographic and projected CRSs, 16-bit PNG, RGB-encoded PNG tiles).
r=$out/dem_reader_fuzzer
translate() { gdal_translate -q "$@"; }
translate -srcwin 40 40 24 24 -co COMPRESS=DEFLATE "$data/gzcommon_dem_squared_129.tif" "$work/a.tif"
withMode 0 "$work/a.tif" "$r/float32_geographic_deflate.tif"
translate -srcwin 500 600 32 32 -co TILED=YES -co BLOCKXSIZE=16 -co BLOCKYSIZE=16 -a_nodata 1500 \
  "$data/zion_srtm3_utm12_30m.tif" "$work/b.tif"
withMode 0 "$work/b.tif" "$r/int16_utm_tiled_nodata.tif"
translate -srcwin 200 200 16 16 -ot Float64 -a_scale 0.5 -a_offset 10 "$data/crater_lake_0513.bt" "$work/c.tif"
withMode 0 "$work/c.tif" "$r/float64_scale_offset.tif"
translate -srcwin 100 100 20 12 -co COMPRESS=LZW -co PREDICTOR=2 "$data/zion_srtm3.tif" "$work/d.tif"
withMode 0 "$work/d.tif" "$r/uint16_lzw_nodata.tif"
translate -of PNG -srcwin 600 600 32 32 -ot UInt16 -a_nodata none "$data/N43W123.hgt" "$work/e.png"
withMode 0 "$work/e.png" "$r/uint16.png"
translate -of PNG -srcwin 100 100 32 32 "$data/loadersgl_terrarium_256.png" "$work/f.png"
withMode 1 "$work/f.png" "$r/terrain_rgb.png"
withMode 2 "$work/f.png" "$r/terrarium.png"
translate -srcwin 100 100 24 24 -co COMPRESS=DEFLATE -a_ullr 0 24 24 0 -a_srs EPSG:3857 \
  "$data/loadersgl_terrarium_256.png" "$work/g.tif"
withMode 2 "$work/g.tif" "$r/terrarium_rgb.tif"
translate -srcwin 0 0 16 16 -b 1 -a_nodata 128 "$data/loadersgl_terrarium_256.png" "$work/h.tif"
withMode 0 "$work/h.tif" "$r/byte_no_crs_voids.tif"

# Vegetation files and LDI blobs: written by a test of libs/vegetation (a small valid .tlv, as
# given and with checksums to recompute, and LDI blobs stored and as payloads), so this needs a
# build: VEGETATION_TESTS names the test executable (default build/release's). Inputs the
# target found bugs with (found_*) are kept.
vegetationTests=${VEGETATION_TESTS:-build/release/tests/vegetation_tests}
mkdir -p "$out/tlv_reader_fuzzer"
TERRALOD_TLV_SEEDS="$PWD/$out/tlv_reader_fuzzer" "$vegetationTests" \
  --gtest_filter='VegetationFuzzSeeds.*' >"$work/seeds.log" || { cat "$work/seeds.log"; exit 1; }

du -sh "$out"
for d in "$out"/*; do echo "$(basename "$d"): $(ls "$d" | wc -l) seeds"; done
