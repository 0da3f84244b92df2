// End-to-end placement of chunk textures: Zion's DEM built with the Landsat image draped over
// it (both on the same 30 m UTM grid), then every texel of the stored colour and normal layers
// decoded (tests/support/bc_decode.h) and compared with the source rasters read directly with
// GDAL at the grid point docs/format.md ("Version 2: textures", Placement) puts the texel on:
// texel (i, j) of node (x, y) lies at grid point (x·c + i·c/(size−1), y·c + j·c/(size−1)),
// grid x = raster column, grid y = rows − 1 − raster row (north up).
//
// Each comparison is repeated against the source displaced by one sample east, west, north
// and south, and flipped north/south inside the chunk (normals: their north component
// negated): those differ clearly more than the aligned comparison, so the bounds below catch
// a texture misplaced by one texel or flipped.

#include <gdal.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <ostream>
#include <string>
#include <vector>

#include "bc_decode.h"
#include "temp_dir.h"
#include "terralod/build/builder.h"
#include "terralod/build/texel_tile.h"
#include "terralod/build/texture_encoder.h"
#include "terralod/format/node_colour.h"
#include "terralod/format/tileset_reader.h"

namespace terralod {
namespace {

constexpr const char* kDem = "zion_srtm3_utm12_30m.tif";
constexpr const char* kImage = "zion_landsat8_rgb_utm12_30m.tif";

// Bounds, from the figures measured on this data (each test prints its own):
//
// Colour. The build feeds the encoder (stb_dxt, BC1) the image's pixels exactly, so the
// stored mip 0 must be byte for byte the encoding of the image at the texels' grid points;
// that is checked first. Against the image itself BC1 is lossy: two RGB565 endpoints and two
// colours between them per 4x4 block, and Landsat's canyon country is busy, so the mean
// |decoded - image| per channel measured 3.2 to 8.1 (of 255) per chunk, 5.2 over the leaves
// tested. The same chunks compared with the image one sample east, west, north or south came
// out 9.7 to 34 (2.8 to 3.2 times the aligned figure) and flipped north/south 22 to 85. As
// the error and the displaced figures both vary with the content from chunk to chunk, no
// one absolute bound separates them; the displaced ones are required to be clearly larger
// for the same chunk instead.
constexpr double kColourBound = 10.0;      // per chunk, mean |decoded - image| of 255
constexpr double kColourMeanBound = 7.0;   // over the leaves tested
constexpr double kColourShifted = 2.0;     // displaced / flipped at least this many times ...
constexpr double kColourShiftedMin = 5.0;  // ... the aligned figure, and at least this
//
// Normals. BC5 stores the normal's east and north components at 8 bits each (steps of
// 2/255): rounding them alone costs 0.17-0.19° on average (measured), the up component being
// rebuilt from them. Each 4x4 block also quantises each component to 8 levels between two
// endpoints, off by up to a 14th of the range the block spans, and blocks on Zion's cliffs
// span wide ranges: the mean angle to the DEM's central-difference normals measured 0.32° to
// 1.1° per chunk (worst texels, on cliffs with up components under 0.5, ~24°). One sample
// displaced: 1.5° to 6.5°, 4.8 to 5.1 times the aligned figure; the north component negated:
// 11° to 40°. The stored layer is also checked against the encoder's own output for the DEM's
// normals (equal up to float rounding of components on a byte boundary).
constexpr double kNormalBoundDegrees = 1.5;
constexpr double kNormalShifted = 3.0;
constexpr double kNormalShiftedMinDegrees = 1.0;
constexpr double kNormalReencodedDegrees = 0.05;

// A raster read whole with GDAL, samples as float, band-interleaved by pixel.
struct Raster {
  int columns = 0, rows = 0, bands = 0;
  double noData = 0;
  bool hasNoData = false;
  std::vector<float> values;
  std::string error;
  // Band `b` at grid point (gx, gy): raster column gx, row rows - 1 - gy.
  float at(int32_t gx, int32_t gy, int b = 0) const {
    return values[(size_t(rows - 1 - gy) * columns + size_t(gx)) * bands + size_t(b)];
  }
  bool inside(int32_t gx, int32_t gy) const {
    return gx >= 0 && gy >= 0 && gx < columns && gy < rows;
  }
};

Raster readRaster(const std::string& path) {
  Raster r;
  GDALAllRegister();
  GDALDatasetH ds = GDALOpen(path.c_str(), GA_ReadOnly);
  if (!ds) {
    r.error = "cannot open " + path;
    return r;
  }
  r.columns = GDALGetRasterXSize(ds);
  r.rows = GDALGetRasterYSize(ds);
  r.bands = GDALGetRasterCount(ds);
  int has = 0;
  r.noData = GDALGetRasterNoDataValue(GDALGetRasterBand(ds, 1), &has);
  r.hasNoData = has != 0;
  r.values.resize(size_t(r.columns) * r.rows * r.bands);
  const int pixel = int(sizeof(float)) * r.bands;
  if (GDALDatasetRasterIO(ds, GF_Read, 0, 0, r.columns, r.rows, r.values.data(), r.columns, r.rows,
                          GDT_Float32, r.bands, nullptr, pixel, int64_t(pixel) * r.columns,
                          sizeof(float)) != CE_None)
    r.error = "cannot read " + path;
  GDALClose(ds);
  return r;
}

struct Chunk {
  uint32_t node = 0;
  int32_t x0 = 0, y0 = 0, cells = 0;  // grid square [x0, x0 + cells] x [y0, y0 + cells]
};

// Mean differences of one layer against the source, aligned and in the comparisons that
// should not match.
struct Comparison {
  double aligned = 0;
  double east = 0, west = 0, north = 0, south = 0, flipped = 0;
  double smallestWrong() const { return std::min({east, west, north, south, flipped}); }
};

std::ostream& operator<<(std::ostream& out, const Comparison& c) {
  char b[200];
  std::snprintf(b, sizeof b,
                "aligned %.3f, east %.3f, west %.3f, north %.3f, south %.3f, "
                "flipped N/S %.3f",
                c.aligned, c.east, c.west, c.north, c.south, c.flipped);
  return out << b;
}

class TextureAlignment : public ::testing::Test {
 protected:
  // Zion with Landsat draped, 8 m at the leaves (coarser meshes build faster than the default
  // 1 m): τ 2 still asks for texels of 4 m there and 8 m a level up, far finer than the 30 m
  // cells, so both levels are capped at one texel per cell (source-limited).
  static BuildOptions zionOptions(const std::string& name, TextureSharing sharing) {
    BuildOptions options;
    options.input = test::testData(kDem);
    options.output = sDir->file(name);
    options.textureImage = test::testData(kImage);
    options.threads = 2;
    options.maxError = 8;
    options.textureSharing = sharing;
    return options;
  }

  static void SetUpTestSuite() {
    sDir = std::make_unique<test::TempDir>();
    sDem = std::make_unique<Raster>(readRaster(test::testData(kDem)));
    sImage = std::make_unique<Raster>(readRaster(test::testData(kImage)));
    // Every chunk its own texture: these tests look at leaves' texels, and at parents' blocks
    // against their children's (what lets children draw their parents' textures by default).
    const BuildOptions options = zionOptions("zion.tlod", TextureSharing::kEveryChunk);
    NullProgress progress;
    auto summary = buildTileset(options, progress, [](const std::string&) {});
    if (!summary) {
      sError = "build failed: " + summary.error().message;
      return;
    }
    sRefine = summary->textureRefine;
    auto reader = TilesetReader::openFile(options.output);
    if (!reader) {
      sError = "open failed: " + reader.error().message;
      return;
    }
    sReader = std::move(reader).value();
  }
  static void TearDownTestSuite() {
    sReader.reset();
    sDem.reset();
    sImage.reset();
    sDir.reset();
  }

  void SetUp() override {
    ASSERT_TRUE(sError.empty()) << sError;
    ASSERT_TRUE(sDem->error.empty()) << sDem->error;
    ASSERT_TRUE(sImage->error.empty()) << sImage->error;
    ASSERT_EQ(sImage->bands, 3);
    ASSERT_EQ(sDem->bands, 1);
    ASSERT_EQ(sDem->columns, sImage->columns);
    ASSERT_EQ(sDem->rows, sImage->rows);
    const TilesetHeader& h = sReader->header();
    ASSERT_TRUE(h.textured());
    ASSERT_EQ(h.sourceColumns, uint32_t(sDem->columns));
    ASSERT_EQ(h.sourceRows, uint32_t(sDem->rows));
    ASSERT_DOUBLE_EQ(h.spacingX, 30.0);
    ASSERT_DOUBLE_EQ(h.spacingY, 30.0);
    ASSERT_EQ(h.verticalScale, 1.0);
    ASSERT_EQ(sRefine, 1u);  // image and DEM share their grid: one image texel per cell
  }

  // Nodes of `level` whose square, widened by `margin` samples, lies inside the rasters on
  // valid heights.
  static std::vector<Chunk> chunksInside(int32_t level, int32_t margin) {
    std::vector<Chunk> out;
    const TilesetHeader& h = sReader->header();
    const int32_t c = h.chunkCells(level);
    const std::vector<NodeRecord>& nodes = sReader->nodes();
    for (uint32_t i = 0; i < nodes.size(); ++i) {
      const NodeRecord& n = nodes[i];
      if (n.level != level) continue;
      const Chunk chunk{i, int32_t(n.x) * c, int32_t(n.y) * c, c};
      bool ok = sDem->inside(chunk.x0 - margin, chunk.y0 - margin) &&
                sDem->inside(chunk.x0 + c + margin, chunk.y0 + c + margin);
      for (int32_t gy = chunk.y0 - margin; ok && gy <= chunk.y0 + c + margin; ++gy)
        for (int32_t gx = chunk.x0 - margin; ok && gx <= chunk.x0 + c + margin; ++gx)
          ok = !(sDem->hasNoData && sDem->at(gx, gy) == float(sDem->noData));
      if (ok) out.push_back(chunk);
    }
    return out;
  }

  // `count` of `chunks` spread evenly over the list.
  static std::vector<Chunk> spread(const std::vector<Chunk>& chunks, size_t count) {
    if (chunks.size() <= count) return chunks;
    std::vector<Chunk> out;
    for (size_t k = 0; k < count; ++k)
      out.push_back(chunks[(2 * k + 1) * chunks.size() / (2 * count)]);
    return out;
  }

  static const TextureLayer* layerOf(const ChunkData& data, TextureLayerKind kind) {
    return data.texture ? data.texture->find(kind) : nullptr;
  }

  // Texel (i, j)'s grid point along one axis; the layer must put whole cells between texels.
  static int32_t gridOf(const Chunk& chunk, uint32_t size, uint32_t k, int32_t origin) {
    return origin + int32_t(k) * (chunk.cells / int32_t(size - 1));
  }

  // Decodes the colour layer's mip 0 and compares every texel with the image.
  static Comparison compareColour(const Chunk& chunk, const TextureLayer& layer) {
    const uint32_t size = layer.size;
    const std::vector<uint8_t> rgb = test::decodeBc1Layer(layer.mips.at(0), size);
    EXPECT_EQ(rgb.size(), size_t(size) * size * 3);
    if (rgb.empty()) return {};
    auto mean = [&](int32_t dx, int32_t dy, bool flip) {
      double sum = 0;
      for (uint32_t j = 0; j < size; ++j)
        for (uint32_t i = 0; i < size; ++i) {
          const int32_t gx = gridOf(chunk, size, i, chunk.x0) + dx;
          const int32_t gy = gridOf(chunk, size, flip ? size - 1 - j : j, chunk.y0) + dy;
          for (int ch = 0; ch < 3; ++ch)
            sum += std::abs(double(rgb[(size_t(j) * size + i) * 3 + size_t(ch)]) -
                            sImage->at(gx, gy, ch));
        }
      return sum / (3.0 * size * size);
    };
    Comparison c;
    c.aligned = mean(0, 0, false);
    c.east = mean(1, 0, false);
    c.west = mean(-1, 0, false);
    c.north = mean(0, 1, false);
    c.south = mean(0, -1, false);
    c.flipped = mean(0, 0, true);
    return c;
  }

  // The image's pixels at the layer's texels, as the encoder takes them (RGB in [0, 1]).
  static TexelTile imageTile(const Chunk& chunk, uint32_t size) {
    TexelTile t(size, 3);
    for (uint32_t j = 0; j < size; ++j)
      for (uint32_t i = 0; i < size; ++i)
        for (int ch = 0; ch < 3; ++ch)
          t.at(i, j)[ch] =
              sImage->at(gridOf(chunk, size, i, chunk.x0), gridOf(chunk, size, j, chunk.y0), ch) /
              255.0f;
    return t;
  }

  // The stored mip 0 is the encoder's output for the image's pixels at the texels' grid
  // points; on failure, the first block that differs.
  static void expectEncodesTheImage(const Chunk& chunk, const TextureLayer& layer) {
    const TextureLayer expected = encodeColorLayer(imageTile(chunk, layer.size), layer.flags);
    const std::vector<uint8_t>& stored = layer.mips.at(0);
    ASSERT_EQ(stored.size(), expected.mips[0].size());
    const uint32_t blocks = (layer.size + 3) / 4;
    for (size_t b = 0; b < stored.size() / 8; ++b)
      if (!std::equal(stored.begin() + b * 8, stored.begin() + b * 8 + 8,
                      expected.mips[0].begin() + b * 8)) {
        ADD_FAILURE() << "BC1 block (" << b % blocks << ", " << b / blocks
                      << ") is not the encoding of the image there";
        return;
      }
  }

  // The DEM's unit normal at grid point (gx, gy) by central differences over 30 m samples.
  static std::array<double, 3> demNormal(int32_t gx, int32_t gy) {
    const double s = 30.0;
    const double dx = (double(sDem->at(gx + 1, gy)) - sDem->at(gx - 1, gy)) / (2 * s);
    const double dy = (double(sDem->at(gx, gy + 1)) - sDem->at(gx, gy - 1)) / (2 * s);
    const double len = std::sqrt(dx * dx + dy * dy + 1);
    return {-dx / len, -dy / len, 1 / len};
  }

  static double degreesBetween(const std::array<double, 3>& a, const std::array<double, 3>& b) {
    const double la = std::hypot(a[0], a[1], a[2]), lb = std::hypot(b[0], b[1], b[2]);
    const double cosine = (a[0] * b[0] + a[1] * b[1] + a[2] * b[2]) / (la * lb);
    return std::acos(std::clamp(cosine, -1.0, 1.0)) * 180.0 / M_PI;
  }

  // Decodes the normal layer's mip 0 and compares every texel with the DEM's normals: mean
  // angle in degrees. `flipped` here is the normal's north component negated (a north/south
  // flip of the map's axes).
  static Comparison compareNormals(const Chunk& chunk, const TextureLayer& layer,
                                   double* worst = nullptr) {
    const uint32_t size = layer.size;
    const std::vector<uint8_t> rg = test::decodeBc5Layer(layer.mips.at(0), size);
    EXPECT_EQ(rg.size(), size_t(size) * size * 2);
    if (rg.empty()) return {};
    auto mean = [&](int32_t dx, int32_t dy, bool flip) {
      double sum = 0;
      for (uint32_t j = 0; j < size; ++j)
        for (uint32_t i = 0; i < size; ++i) {
          const size_t k = (size_t(j) * size + i) * 2;
          std::array<double, 3> stored = test::normalFromRg8(rg[k], rg[k + 1]);
          if (flip) stored[1] = -stored[1];
          const double a = degreesBetween(stored, demNormal(gridOf(chunk, size, i, chunk.x0) + dx,
                                                            gridOf(chunk, size, j, chunk.y0) + dy));
          sum += a;
          if (worst && dx == 0 && dy == 0 && !flip) *worst = std::max(*worst, a);
        }
      return sum / (double(size) * size);
    };
    Comparison c;
    c.aligned = mean(0, 0, false);
    c.east = mean(1, 0, false);
    c.west = mean(-1, 0, false);
    c.north = mean(0, 1, false);
    c.south = mean(0, -1, false);
    c.flipped = mean(0, 0, true);
    return c;
  }

  // Mean angle (degrees) between the stored mip 0 and the encoder's own output for the DEM's
  // normals at the texels' grid points.
  static double reencodedNormalDegrees(const Chunk& chunk, const TextureLayer& layer) {
    const uint32_t size = layer.size;
    TexelTile t(size, 3);
    for (uint32_t j = 0; j < size; ++j)
      for (uint32_t i = 0; i < size; ++i) {
        const auto n =
            demNormal(gridOf(chunk, size, i, chunk.x0), gridOf(chunk, size, j, chunk.y0));
        for (int c = 0; c < 3; ++c) t.at(i, j)[c] = float(n[size_t(c)]);
      }
    const std::vector<uint8_t> a = test::decodeBc5Layer(layer.mips.at(0), size),
                               b = test::decodeBc5Layer(encodeNormalLayer(t, layer.flags).mips[0],
                                                        size);
    if (a.empty() || a.size() != b.size()) return 180;
    double sum = 0;
    for (size_t k = 0; k < a.size(); k += 2)
      sum +=
          degreesBetween(test::normalFromRg8(a[k], a[k + 1]), test::normalFromRg8(b[k], b[k + 1]));
    return sum / (double(size) * size);
  }

  static inline std::unique_ptr<test::TempDir> sDir;
  static inline std::unique_ptr<Raster> sDem, sImage;
  static inline std::unique_ptr<TilesetReader> sReader;
  static inline std::string sError;
  static inline uint32_t sRefine = 0;
};

std::string where(const Chunk& c, uint32_t level) {
  return "node " + std::to_string(c.node) + " level " + std::to_string(level) + " grid (" +
         std::to_string(c.x0) + ", " + std::to_string(c.y0) + ") + " + std::to_string(c.cells);
}

// Leaves well inside the data: each texel is the image's pixel at its grid point, to BC1's
// error.
TEST_F(TextureAlignment, ColourOfLeavesIsTheImageAtEachTexelsGridPoint) {
  const int32_t leaf = sReader->header().depth();
  const std::vector<Chunk> chunks = spread(chunksInside(leaf, 2), 8);
  ASSERT_GE(chunks.size(), 4u);
  double worstAligned = 0, leastWrong = 1e9, meanAligned = 0;
  for (const Chunk& chunk : chunks) {
    SCOPED_TRACE(where(chunk, uint32_t(leaf)));
    auto data = sReader->readChunkData(chunk.node);
    ASSERT_TRUE(data.ok()) << data.error().message;
    const TextureLayer* layer = layerOf(*data, TextureLayerKind::kColor);
    ASSERT_NE(layer, nullptr);
    ASSERT_EQ(layer->encoding, TextureEncoding::kBc1);
    ASSERT_TRUE(layer->sourceLimited());  // see maxError above
    ASSERT_EQ(layer->size - 1, uint32_t(chunk.cells));
    expectEncodesTheImage(chunk, *layer);
    const Comparison c = compareColour(chunk, *layer);
    std::printf("colour  %s: %s\n", where(chunk, uint32_t(leaf)).c_str(),
                testing::PrintToString(c).c_str());
    EXPECT_LT(c.aligned, kColourBound) << c;
    EXPECT_GT(c.smallestWrong(), std::max(kColourShifted * c.aligned, kColourShiftedMin)) << c;
    worstAligned = std::max(worstAligned, c.aligned);
    leastWrong = std::min(leastWrong, c.smallestWrong());
    meanAligned += c.aligned / double(chunks.size());
  }
  std::printf(
      "colour leaves: mean aligned %.3f, worst aligned %.3f, least displaced %.3f (of 255)\n",
      meanAligned, worstAligned, leastWrong);
  EXPECT_LT(meanAligned, kColourMeanBound);
}

// A parent a level up, source-limited (one texel per cell): its texels are its children's
// side by side (mip 0 reuses their blocks), still on the image's pixels.
TEST_F(TextureAlignment, ColourOfASourceLimitedParentIsTheImageAtEachTexelsGridPoint) {
  const int32_t level = sReader->header().depth() - 1;
  ASSERT_GE(level, 0);
  const std::vector<Chunk> chunks = chunksInside(level, 2);
  ASSERT_FALSE(chunks.empty());
  // The one nearest the middle of the data.
  const double mx = sDem->columns / 2.0, my = sDem->rows / 2.0;
  const Chunk chunk = *std::min_element(chunks.begin(), chunks.end(), [&](auto& a, auto& b) {
    return std::hypot(a.x0 + a.cells / 2.0 - mx, a.y0 + a.cells / 2.0 - my) <
           std::hypot(b.x0 + b.cells / 2.0 - mx, b.y0 + b.cells / 2.0 - my);
  });
  SCOPED_TRACE(where(chunk, uint32_t(level)));
  ASSERT_NE(sReader->nodes()[chunk.node].childMask, 0);
  auto data = sReader->readChunkData(chunk.node);
  ASSERT_TRUE(data.ok()) << data.error().message;
  const TextureLayer* layer = layerOf(*data, TextureLayerKind::kColor);
  ASSERT_NE(layer, nullptr);
  ASSERT_TRUE(layer->sourceLimited());
  ASSERT_EQ(layer->size - 1, uint32_t(chunk.cells));
  expectEncodesTheImage(chunk, *layer);
  const Comparison c = compareColour(chunk, *layer);
  std::printf("colour  %s: %s\n", where(chunk, uint32_t(level)).c_str(),
              testing::PrintToString(c).c_str());
  EXPECT_LT(c.aligned, kColourBound) << c;
  EXPECT_GT(c.smallestWrong(), std::max(kColourShifted * c.aligned, kColourShiftedMin)) << c;
}

// The normal map of leaves (and of the parent above) against the DEM's own normals by
// central differences.
TEST_F(TextureAlignment, NormalsOfLeavesAreTheDemsNormalsAtEachTexelsGridPoint) {
  const int32_t leaf = sReader->header().depth();
  std::vector<std::pair<Chunk, int32_t>> chunks;
  for (const Chunk& c : spread(chunksInside(leaf, 2), 4)) chunks.push_back({c, leaf});
  ASSERT_GE(chunks.size(), 2u);
  if (const auto parents = chunksInside(leaf - 1, 2); !parents.empty())
    chunks.push_back({parents[parents.size() / 2], leaf - 1});
  for (const auto& [chunk, level] : chunks) {
    SCOPED_TRACE(where(chunk, uint32_t(level)));
    auto data = sReader->readChunkData(chunk.node);
    ASSERT_TRUE(data.ok()) << data.error().message;
    const TextureLayer* layer = layerOf(*data, TextureLayerKind::kNormal);
    ASSERT_NE(layer, nullptr);
    ASSERT_EQ(layer->encoding, TextureEncoding::kBc5);
    ASSERT_TRUE(layer->sourceLimited());  // capped at one texel per DEM cell
    ASSERT_EQ(layer->size - 1, uint32_t(chunk.cells));
    double worst = 0;
    const Comparison c = compareNormals(chunk, *layer, &worst);
    const double reencoded = reencodedNormalDegrees(chunk, *layer);
    std::printf("normals %s: %s degrees, worst aligned %.2f, against re-encoding %.4f\n",
                where(chunk, uint32_t(level)).c_str(), testing::PrintToString(c).c_str(), worst,
                reencoded);
    EXPECT_LT(reencoded, kNormalReencodedDegrees);
    EXPECT_LT(c.aligned, kNormalBoundDegrees) << c;
    EXPECT_GT(c.smallestWrong(), std::max(kNormalShifted * c.aligned, kNormalShiftedMinDegrees))
        << c;
  }
}

// A parent holding its children unresampled (source-limited levels) is, at every mip level
// whose blocks line up, its children's blocks side by side: the same pixels on both sides of
// a split or merge (what keeps bench's image pops small).
TEST_F(TextureAlignment, ParentMipLevelsAreTheirChildrensBlocksSideBySide) {
  const auto& nodes = sReader->nodes();
  int checked = 0;
  for (uint32_t i = 0; i < nodes.size() && checked < 3; ++i) {
    const NodeRecord& n = nodes[i];
    if (n.childMask != 15) continue;
    auto parent = sReader->readChunkData(i).value();
    std::array<ChunkData, 4> children;
    for (uint32_t q = 0; q < 4; ++q) children[q] = sReader->readChunkData(n.firstChild + q).value();
    for (size_t layer = 0; layer < 2; ++layer) {
      const TextureLayer& p = parent.texture->layers[layer];
      const TextureLayer& c0 = children[0].texture->layers[layer];
      if (p.size != 2 * c0.size - 1) continue;  // resampled, not unresampled
      const size_t block = p.encoding == TextureEncoding::kBc1 ? 8 : 16;
      for (uint32_t m = 1; m < c0.mips.size(); ++m) {
        const uint32_t childSide = mipSize(c0.size, m);
        if (childSide % 4 != 0) continue;
        const uint32_t cb = childSide / 4, pb = 2 * cb;
        ASSERT_EQ(mipSize(p.size, m), 2 * childSide);
        for (uint32_t q = 0; q < 4; ++q) {
          const auto& child = children[q].texture->layers[layer].mips[m];
          for (uint32_t by = 0; by < cb; ++by)
            EXPECT_EQ(0, std::memcmp(p.mips[m].data() +
                                         (size_t((q >> 1) * cb + by) * pb + (q & 1) * cb) * block,
                                     child.data() + size_t(by) * cb * block, cb * block))
                << "node " << i << " layer " << layer << " mip " << m << " quadrant " << q;
        }
      }
      ++checked;
    }
  }
  EXPECT_GE(checked, 2) << "no unresampled parent with four children was found";
}

// By default (TextureSharing::kInherit) the children of a parent that holds them unresampled
// store no texture and draw their part of the parent's: the same texels as their own, except
// the east and north border, which the parent encodes in its neighbour's BC1 block (the
// neighbour's own encoding of the same texel: BC1's error, which on a photograph reaches a few
// dozen levels on single texels).
TEST_F(TextureAlignment, ChildrenSharingTheirParentsTextureDrawTheirOwnTexels) {
  const BuildOptions options = zionOptions("zion-shared.tlod", TextureSharing::kInherit);
  NullProgress progress;
  auto summary = buildTileset(options, progress, [](const std::string&) {});
  ASSERT_TRUE(summary.ok()) << summary.error().message;
  auto shared = TilesetReader::openFile(options.output);
  ASSERT_TRUE(shared.ok()) << shared.error().message;
  const TilesetReader& t = **shared;
  ASSERT_EQ(t.nodes().size(), sReader->nodes().size());
  EXPECT_GE(t.header().version, 5u);  // sharing parents' textures began with version 5
  EXPECT_LT(t.header().fileBytes, sReader->header().fileBytes);
  int compared = 0;
  double borderSum = 0, borderCount = 0;
  for (uint32_t i = 0; i < t.nodes().size(); ++i) {
    if (!t.nodes()[i].inheritsTexture()) continue;
    EXPECT_EQ(t.nodes()[i].textureBytes, 0u);
    auto own = readNodeColour(*sReader, i);
    auto drawn = readNodeColour(t, i);
    ASSERT_TRUE(own.ok() && drawn.ok());
    ASSERT_EQ(own->size, drawn->size) << "chunk " << i;
    const uint32_t n = own->size;
    int inside = 0, border = 0;
    for (uint32_t y = 0; y < n; ++y)
      for (uint32_t x = 0; x < n; ++x)
        for (size_t c = 0; c < 3; ++c) {
          const size_t k = (size_t(y) * n + x) * 3 + c;
          const int d = std::abs(int(own->rgb[k]) - int(drawn->rgb[k]));
          if (x + 1 == n || y + 1 == n) {
            border = std::max(border, d);
            borderSum += d;
            ++borderCount;
          } else {
            inside = std::max(inside, d);
          }
        }
    EXPECT_EQ(inside, 0) << "chunk " << i;
    EXPECT_LE(border, 96) << "chunk " << i;
    ++compared;
  }
  EXPECT_GE(compared, 8) << "no chunk shares its parent's texture";
  const double borderMean = borderSum / std::max(1.0, borderCount);
  std::printf("shared textures: %d chunks, border texels differ by %.2f/255 on average\n", compared,
              borderMean);
  EXPECT_LT(borderMean, 4.0);
}

}  // namespace
}  // namespace terralod
