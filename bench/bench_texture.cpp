// Chunk texture storage: size, build cost, CPU decode cost and quality of the candidate
// encodings, on real tiles (Landsat 8 colour and SRTM normals of Zion, tests/data).
//
//  - GPU block compression as the build stores it (encodeColorLayer: BC1 + mips,
//    encodeNormalLayer: BC5 + mips), optionally with zstd level 3 over the layer bytes;
//  - JPEG (q90, q75) of the RGB tile and PNG of the RGB and of the RG normal tile (stb).
//
// Every benchmark processes the same three tiles (cut at three offsets well inside the data)
// per iteration; items processed = level-0 texels (size² per tile), so items_per_second is
// texels/s and "time_per_texel" its inverse (CPU seconds). Sizes are per level-0 texel:
//   bytes_per_texel       stored bytes (BC: the layer with its whole mip chain unless noted;
//                         JPEG/PNG: level 0 only, the client would build mips after decoding)
//   bytes_per_texel_mip0  BC: level 0 alone
//   gpu_bytes_per_texel   resident GPU memory with a full mip chain: BC as stored; a decoded
//                         JPEG/PNG is uploaded as RGBA8 (4 B, RGB8 is padded by drivers) or
//                         RG8 (2 B) per texel, times the chain's 4/3-ish factor
//   psnr_db               level 0 against the 8-bit source (colour: RGB; normal: x, y bytes)
//
// BC data has no CPU decode: the GPU samples the blocks as uploaded (glCompressedTexImage2D),
// so its "decode" cost is the upload memcpy alone. The decode benchmarks below time what a
// client must do on the CPU before upload: JPEG/PNG decompression, or zstd of BC data.
//
//   build/helper2/bench/bench_texture --benchmark_repetitions=3
//   --benchmark_report_aggregates_only=true

#include <benchmark/benchmark.h>
#include <gdal_priv.h>
#include <stb_image.h>
#include <stb_image_write.h>
#include <zstd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <string>
#include <vector>

#include "bc_decode.h"
#include "terralod/build/texel_tile.h"
#include "terralod/build/texture_encoder.h"
#include "terralod/format/texture_codec.h"

#ifndef TERRALOD_TEST_DATA_DIR
#define TERRALOD_TEST_DATA_DIR "tests/data"
#endif

namespace terralod {
namespace {

constexpr double kSpacing = 30.0;  // metres, both rasters' grid
constexpr std::array<std::array<int, 2>, 3> kOffsets = {{{350, 450}, {550, 750}, {700, 1050}}};

[[noreturn]] void die(const std::string& what) {
  std::fprintf(stderr, "bench_texture: %s\n", what.c_str());
  std::exit(1);
}

// One tile at one offset, in every form the benchmarks need.
struct Tile {
  uint32_t size = 0;
  std::vector<uint8_t> rgb;  // 8-bit source colour, size² × 3
  std::vector<uint8_t> rg;   // normal x, y as the BC5 encoder quantises them, size² × 2
  TexelTile color;           // rgb / 255
  TexelTile normal;          // unit normals (east, north, up)
};

std::vector<uint8_t> readWindow(const char* path, int x0, int y0, int w, int h, int bands,
                                GDALDataType type, int typeBytes) {
  GDALAllRegister();
  GDALDataset* ds = static_cast<GDALDataset*>(GDALOpen(path, GA_ReadOnly));
  if (!ds) die(std::string("cannot open ") + path);
  if (ds->GetRasterCount() < bands) die(std::string("too few bands in ") + path);
  std::vector<uint8_t> out(size_t(w) * h * bands * typeBytes);
  std::vector<int> bandList(bands);
  for (int b = 0; b < bands; ++b) bandList[b] = b + 1;
  // Pixel-interleaved: pixel stride bands × type, line stride w × that, band stride type.
  if (ds->RasterIO(GF_Read, x0, y0, w, h, out.data(), w, h, type, bands, bandList.data(),
                   bands * typeBytes, GSpacing(w) * bands * typeBytes, typeBytes) != CE_None)
    die(std::string("cannot read ") + path);
  GDALClose(ds);
  return out;
}

Tile makeTile(uint32_t size, int x0, int y0) {
  Tile t;
  t.size = size;
  const int n = int(size);
  t.rgb = readWindow(TERRALOD_TEST_DATA_DIR "/zion_landsat8_rgb_utm12_30m.tif", x0, y0, n, n, 3,
                     GDT_Byte, 1);
  t.color = TexelTile(size, 3);
  for (size_t i = 0; i < t.rgb.size(); ++i) t.color.values[i] = float(t.rgb[i]) / 255.0f;

  // Heights with a one-sample margin for central differences.
  const std::vector<uint8_t> raw = readWindow(TERRALOD_TEST_DATA_DIR "/zion_srtm3_utm12_30m.tif",
                                              x0 - 1, y0 - 1, n + 2, n + 2, 1, GDT_Float32, 4);
  std::vector<float> h((n + 2) * (n + 2));
  std::memcpy(h.data(), raw.data(), raw.size());
  for (float v : h)
    if (v <= -32000.0f) die("nodata in the height window; move the offset");
  auto at = [&](int x, int y) { return h[size_t(y + 1) * (n + 2) + (x + 1)]; };
  t.normal = TexelTile(size, 3);
  t.rg.resize(size_t(n) * n * 2);
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      // Rows run south: north is row - 1.
      const float dx = float((at(x + 1, y) - at(x - 1, y)) / (2.0 * kSpacing));
      const float dy = float((at(x, y - 1) - at(x, y + 1)) / (2.0 * kSpacing));
      const float inv = 1.0f / std::sqrt(dx * dx + dy * dy + 1.0f);
      float* v = t.normal.at(uint32_t(x), uint32_t(y));
      v[0] = -dx * inv;
      v[1] = -dy * inv;
      v[2] = inv;
      // The same quantisation as encodeNormalLayer's input to BC5.
      for (int c = 0; c < 2; ++c)
        t.rg[(size_t(y) * n + x) * 2 + c] =
            uint8_t(std::clamp(0.5f * (v[c] + 1.0f) * 255.0f + 0.5f, 0.0f, 255.0f));
    }
  return t;
}

const std::vector<Tile>& tiles(uint32_t size) {
  static std::map<uint32_t, std::vector<Tile>> cache;
  auto it = cache.find(size);
  if (it == cache.end()) {
    std::vector<Tile> v;
    for (const auto& o : kOffsets) v.push_back(makeTile(size, o[0], o[1]));
    it = cache.emplace(size, std::move(v)).first;
  }
  return it->second;
}

double texelsOf(const std::vector<Tile>& ts) {
  double n = 0;
  for (const Tile& t : ts) n += double(t.size) * t.size;
  return n;
}

// Texels of a full mip chain relative to level 0.
double chainFactor(uint32_t size) {
  double all = 0;
  for (uint32_t m = 0; m < mipCount(size); ++m) all += double(mipSize(size, m)) * mipSize(size, m);
  return all / (double(size) * size);
}

std::vector<uint8_t> layerBytes(const TextureLayer& layer) {
  std::vector<uint8_t> out;
  for (const auto& m : layer.mips) out.insert(out.end(), m.begin(), m.end());
  return out;
}

std::vector<uint8_t> zstd(const std::vector<uint8_t>& in, int level) {
  std::vector<uint8_t> out(ZSTD_compressBound(in.size()));
  const size_t n = ZSTD_compress(out.data(), out.size(), in.data(), in.size(), level);
  if (ZSTD_isError(n)) die("ZSTD_compress failed");
  out.resize(n);
  return out;
}

void appendTo(void* context, void* data, int size) {
  auto* out = static_cast<std::vector<uint8_t>*>(context);
  const auto* p = static_cast<const uint8_t*>(data);
  out->insert(out->end(), p, p + size);
}

std::vector<uint8_t> jpeg(const Tile& t, int quality) {
  std::vector<uint8_t> out;
  if (!stbi_write_jpg_to_func(appendTo, &out, int(t.size), int(t.size), 3, t.rgb.data(), quality))
    die("stbi_write_jpg_to_func failed");
  return out;
}

std::vector<uint8_t> png(const Tile& t, bool normal) {
  std::vector<uint8_t> out;
  const int comp = normal ? 2 : 3;
  const auto& data = normal ? t.rg : t.rgb;
  if (!stbi_write_png_to_func(appendTo, &out, int(t.size), int(t.size), comp, data.data(),
                              int(t.size) * comp))
    die("stbi_write_png_to_func failed");
  return out;
}

// BC decoding for the quality counters only (the GPU does it in hardware): the tests'
// reference decoders (tests/support/bc_decode.h).
std::vector<uint8_t> decodeBc1(const std::vector<uint8_t>& blocks, uint32_t size) {
  return test::decodeBc1Layer(blocks, size);
}
std::vector<uint8_t> decodeBc5(const std::vector<uint8_t>& blocks, uint32_t size) {
  return test::decodeBc5Layer(blocks, size);
}

// Accumulates squared error over several tiles; PSNR of the lot (8-bit peak).
struct Psnr {
  double sse = 0, n = 0;
  void add(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b) {
    if (a.size() != b.size()) die("PSNR of different sizes");
    for (size_t i = 0; i < a.size(); ++i) {
      const double d = double(a[i]) - double(b[i]);
      sse += d * d;
    }
    n += double(a.size());
  }
  double db() const { return sse == 0 ? 99.0 : 10.0 * std::log10(255.0 * 255.0 * n / sse); }
};

void setTexels(benchmark::State& state, const std::vector<Tile>& ts) {
  const double texels = texelsOf(ts);
  state.SetItemsProcessed(int64_t(state.iterations() * texels));
  // CPU seconds per level-0 texel (printed with an SI prefix, e.g. "7.2n" = 7.2 ns).
  state.counters["time_per_texel"] = benchmark::Counter(
      texels, benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

// --- Build (encode) throughput, with sizes and quality.

void encodeBc1(benchmark::State& state) {
  const auto& ts = tiles(uint32_t(state.range(0)));
  std::vector<TextureLayer> layers(ts.size());
  for (auto _ : state)
    for (size_t i = 0; i < ts.size(); ++i) {
      layers[i] = encodeColorLayer(ts[i].color, 0);
      benchmark::DoNotOptimize(layers[i].mips.data());
    }
  double all = 0, mip0 = 0;
  Psnr q;
  for (size_t i = 0; i < ts.size(); ++i) {
    all += double(layerBytes(layers[i]).size());
    mip0 += double(layers[i].mips[0].size());
    q.add(decodeBc1(layers[i].mips[0], ts[i].size), ts[i].rgb);
  }
  setTexels(state, ts);
  state.counters["bytes_per_texel"] = all / texelsOf(ts);
  state.counters["bytes_per_texel_mip0"] = mip0 / texelsOf(ts);
  state.counters["gpu_bytes_per_texel"] = all / texelsOf(ts);
  state.counters["psnr_db"] = q.db();
}
BENCHMARK(encodeBc1)->Name("encode/bc1_mips")->Arg(65)->Arg(129);

void encodeBc5(benchmark::State& state) {
  const auto& ts = tiles(uint32_t(state.range(0)));
  std::vector<TextureLayer> layers(ts.size());
  for (auto _ : state)
    for (size_t i = 0; i < ts.size(); ++i) {
      layers[i] = encodeNormalLayer(ts[i].normal, 0);
      benchmark::DoNotOptimize(layers[i].mips.data());
    }
  double all = 0, mip0 = 0;
  Psnr q;
  for (size_t i = 0; i < ts.size(); ++i) {
    all += double(layerBytes(layers[i]).size());
    mip0 += double(layers[i].mips[0].size());
    q.add(decodeBc5(layers[i].mips[0], ts[i].size), ts[i].rg);
  }
  setTexels(state, ts);
  state.counters["bytes_per_texel"] = all / texelsOf(ts);
  state.counters["bytes_per_texel_mip0"] = mip0 / texelsOf(ts);
  state.counters["gpu_bytes_per_texel"] = all / texelsOf(ts);
  state.counters["psnr_db"] = q.db();
}
BENCHMARK(encodeBc5)->Name("encode/bc5_mips")->Arg(65)->Arg(129);

// zstd level 3 over a BC layer's bytes (all mips), on top of the BC encode (timed: zstd only).
void encodeBcZstd(benchmark::State& state, bool normal) {
  const auto& ts = tiles(uint32_t(state.range(0)));
  std::vector<std::vector<uint8_t>> raw, packed(ts.size());
  for (const Tile& t : ts)
    raw.push_back(
        layerBytes(normal ? encodeNormalLayer(t.normal, 0) : encodeColorLayer(t.color, 0)));
  for (auto _ : state)
    for (size_t i = 0; i < ts.size(); ++i) {
      packed[i] = zstd(raw[i], 3);
      benchmark::DoNotOptimize(packed[i].data());
    }
  double bytes = 0, rawBytes = 0;
  for (size_t i = 0; i < ts.size(); ++i) {
    bytes += double(packed[i].size());
    rawBytes += double(raw[i].size());
  }
  setTexels(state, ts);
  state.counters["bytes_per_texel"] = bytes / texelsOf(ts);
  state.counters["gpu_bytes_per_texel"] = rawBytes / texelsOf(ts);
  state.counters["zstd_ratio"] = rawBytes / bytes;
}
BENCHMARK_CAPTURE(encodeBcZstd, bc1, false)->Name("encode/bc1_mips_zstd3")->Arg(65)->Arg(129);
BENCHMARK_CAPTURE(encodeBcZstd, bc5, true)->Name("encode/bc5_mips_zstd3")->Arg(65)->Arg(129);

void encodeJpeg(benchmark::State& state, int quality) {
  const auto& ts = tiles(uint32_t(state.range(0)));
  std::vector<std::vector<uint8_t>> files(ts.size());
  for (auto _ : state)
    for (size_t i = 0; i < ts.size(); ++i) {
      files[i] = jpeg(ts[i], quality);
      benchmark::DoNotOptimize(files[i].data());
    }
  double bytes = 0;
  Psnr q;
  for (size_t i = 0; i < ts.size(); ++i) {
    bytes += double(files[i].size());
    int w = 0, h = 0, c = 0;
    stbi_uc* px = stbi_load_from_memory(files[i].data(), int(files[i].size()), &w, &h, &c, 3);
    if (!px) die("stbi_load_from_memory failed");
    q.add(std::vector<uint8_t>(px, px + size_t(w) * h * 3), ts[i].rgb);
    stbi_image_free(px);
  }
  setTexels(state, ts);
  state.counters["bytes_per_texel"] = bytes / texelsOf(ts);
  state.counters["gpu_bytes_per_texel"] = 4.0 * chainFactor(ts[0].size);  // RGBA8 + mips
  state.counters["psnr_db"] = q.db();
}
BENCHMARK_CAPTURE(encodeJpeg, q90, 90)->Name("encode/jpeg_q90")->Arg(65)->Arg(129);
BENCHMARK_CAPTURE(encodeJpeg, q75, 75)->Name("encode/jpeg_q75")->Arg(65)->Arg(129);

void encodePng(benchmark::State& state, bool normal) {
  const auto& ts = tiles(uint32_t(state.range(0)));
  std::vector<std::vector<uint8_t>> files(ts.size());
  for (auto _ : state)
    for (size_t i = 0; i < ts.size(); ++i) {
      files[i] = png(ts[i], normal);
      benchmark::DoNotOptimize(files[i].data());
    }
  double bytes = 0;
  for (const auto& f : files) bytes += double(f.size());
  setTexels(state, ts);
  state.counters["bytes_per_texel"] = bytes / texelsOf(ts);
  // Lossless: RGBA8 (colour) or RG8 (normal), plus mips built after decoding.
  state.counters["gpu_bytes_per_texel"] = (normal ? 2.0 : 4.0) * chainFactor(ts[0].size);
}
BENCHMARK_CAPTURE(encodePng, rgb, false)->Name("encode/png_rgb")->Arg(65)->Arg(129);
BENCHMARK_CAPTURE(encodePng, rg, true)->Name("encode/png_rg_normal")->Arg(65)->Arg(129);

// --- CPU decode cost before upload. (BC: none; the GPU samples the blocks directly.)

void decodeImage(benchmark::State& state,
                 int kind) {  // 0 jpeg q90, 1 jpeg q75, 2 png rgb, 3 png rg
  const auto& ts = tiles(uint32_t(state.range(0)));
  std::vector<std::vector<uint8_t>> files;
  for (const Tile& t : ts)
    files.push_back(kind == 0 ? jpeg(t, 90) : kind == 1 ? jpeg(t, 75) : png(t, kind == 3));
  // Ask for what would be uploaded: RGBA8 for colour, RG8 for normals.
  const int want = kind == 3 ? 2 : 4;
  for (auto _ : state)
    for (const auto& f : files) {
      int w = 0, h = 0, c = 0;
      stbi_uc* px = stbi_load_from_memory(f.data(), int(f.size()), &w, &h, &c, want);
      if (!px) die("stbi_load_from_memory failed");
      benchmark::DoNotOptimize(px);
      stbi_image_free(px);
    }
  setTexels(state, ts);
}
BENCHMARK_CAPTURE(decodeImage, jpeg_q90, 0)->Name("decode/jpeg_q90")->Arg(65)->Arg(129);
BENCHMARK_CAPTURE(decodeImage, jpeg_q75, 1)->Name("decode/jpeg_q75")->Arg(65)->Arg(129);
BENCHMARK_CAPTURE(decodeImage, png_rgb, 2)->Name("decode/png_rgb")->Arg(65)->Arg(129);
BENCHMARK_CAPTURE(decodeImage, png_rg, 3)->Name("decode/png_rg_normal")->Arg(65)->Arg(129);

void decodeBcZstd(benchmark::State& state, bool normal) {
  const auto& ts = tiles(uint32_t(state.range(0)));
  std::vector<std::vector<uint8_t>> raw, packed;
  for (const Tile& t : ts) {
    raw.push_back(
        layerBytes(normal ? encodeNormalLayer(t.normal, 0) : encodeColorLayer(t.color, 0)));
    packed.push_back(zstd(raw.back(), 3));
  }
  std::vector<uint8_t> out(std::max_element(raw.begin(), raw.end(), [](auto& a, auto& b) {
                             return a.size() < b.size();
                           })->size());
  for (auto _ : state)
    for (size_t i = 0; i < packed.size(); ++i) {
      const size_t n = ZSTD_decompress(out.data(), out.size(), packed[i].data(), packed[i].size());
      if (ZSTD_isError(n) || n != raw[i].size()) die("ZSTD_decompress failed");
      benchmark::DoNotOptimize(out.data());
    }
  setTexels(state, ts);
}
BENCHMARK_CAPTURE(decodeBcZstd, bc1, false)->Name("decode/zstd_bc1_mips")->Arg(65)->Arg(129);
BENCHMARK_CAPTURE(decodeBcZstd, bc5, true)->Name("decode/zstd_bc5_mips")->Arg(65)->Arg(129);

}  // namespace
}  // namespace terralod

BENCHMARK_MAIN();
