// `build --kind vipm` (docs/format.md "VIPM tilesets"), checked from the file alone against the
// source: every blob decodes and reconstructs, roots are exactly their children's coarsest
// levels, node and header fields are as documented, flanges cover every level's border
// deviation (recomputed here by brute force), and the output does not depend on threads.

#include <gdal_priv.h>
#include <gdal_utils.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <tuple>

#include "load_heights.h"
#include "temp_dir.h"
#include "terralod/build/builder.h"
#include "terralod/build/vipm_chunks.h"
#include "terralod/format/texture_decode.h"
#include "terralod/format/tileset_reader.h"
#include "terralod/raster/synthetic_dem_writer.h"
#include "terralod/raster/void_fill.h"
#include "terralod/vipm/vipm_levels.h"
#include "terralod/vipm/vipm_storage.h"

namespace terralod {
namespace {

using test::readWholeFile;
using test::TempDir;
using test::testData;

// A corner as the world sees it: grid point, height, material.
using Corner = std::tuple<uint32_t, uint32_t, double, uint8_t>;
using Triangle = std::array<Corner, 3>;

// The triangle with its smallest corner first (the codec may rotate corners).
Triangle canonical(Triangle t) {
  while (!(t[0] <= t[1] && t[0] <= t[2])) std::rotate(t.begin(), t.begin() + 1, t.end());
  return t;
}

// Cuts a window out of a raster (GDAL's translate), keeping its georeferencing.
std::string crop(const std::string& source, const std::string& target, int x, int y, int w, int h) {
  GDALAllRegister();
  GDALDatasetUniquePtr src(GDALDataset::Open(source.c_str(), GDAL_OF_RASTER));
  EXPECT_TRUE(src);
  const std::string args[] = {"-srcwin", std::to_string(x), std::to_string(y), std::to_string(w),
                              std::to_string(h)};
  std::vector<char*> argv;
  for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  GDALTranslateOptions* options = GDALTranslateOptionsNew(argv.data(), nullptr);
  GDALClose(GDALTranslate(target.c_str(), src.get(), options, nullptr));
  GDALTranslateOptionsFree(options);
  return target;
}

std::string synth(const TempDir& dir, int64_t columns, int64_t rows) {
  SyntheticDemOptions o;
  o.output = dir.file("synth.tif");
  o.columns = columns;
  o.rows = rows;
  o.seed = 7;
  o.spacing = 10.0;
  o.threads = 1;
  NullProgress progress;
  EXPECT_TRUE(writeSyntheticDem(o, progress).ok());
  return o.output;
}

BuildOptions vipmOptions(const std::string& input, const std::string& output) {
  BuildOptions o;
  o.input = input;
  o.output = output;
  o.kind = TilesetKind::kVipm;
  o.textures = false;
  o.threads = 2;
  o.vipmUpperLevels = 0;  // the leaves and roots (vipm_upper_levels_test: the levels above)
  return o;
}

BuildSummary build(const BuildOptions& o) {
  NullProgress progress;
  auto s = buildTileset(o, progress, [](const std::string&) {});
  EXPECT_TRUE(s.ok()) << (s.ok() ? "" : s.error().message);
  return s.ok() ? *s : BuildSummary{};
}

Heightfield sourceHeights(const std::string& path) {
  auto dem = DemReader::open(path, {});
  EXPECT_TRUE(dem.ok());
  NullProgress progress;
  auto h = loadHeights(**dem, progress);
  EXPECT_TRUE(h.ok());
  EXPECT_TRUE(fillVoids(*h, path).ok());
  return std::move(h).value();
}

struct Chunk {
  VipmChunkData data;
  UnpackedChunk unpacked;
};

// The largest distance between a border point's source height and the border polyline, over
// every level: recomputed from the stored chunk, each level from scratch.
double bruteBorderDeviation(const Chunk& c, const Heightfield& h, uint32_t x0, uint32_t y0) {
  const uint32_t n = c.data.vertexCount(), w = c.data.width, hh = c.data.height;
  std::vector<uint32_t> border;
  for (uint32_t v = 0; v < n; ++v) {
    const uint32_t x = c.data.points[v] % w, y = c.data.points[v] / w;
    if (x == 0 || y == 0 || x == w - 1 || y == hh - 1) border.push_back(v);
  }
  double worst = 0.0;
  for (uint32_t j = 0; j <= c.data.collapseCount(); ++j) {
    if (j > 0 && std::find(border.begin(), border.end(), n - j) == border.end()) continue;
    for (int side = 0; side < 4; ++side) {
      std::map<uint32_t, double> line;  // position along the side -> stored height
      for (uint32_t v : border) {
        if (v >= n - j) continue;
        const uint32_t x = c.data.points[v] % w, y = c.data.points[v] / w;
        const bool on = side == 0   ? y == 0
                        : side == 1 ? y == hh - 1
                        : side == 2 ? x == 0
                                    : x == w - 1;
        if (on) line[side < 2 ? x : y] = c.unpacked.positions[v][2];
      }
      for (auto a = line.begin(), b = std::next(a); b != line.end(); ++a, ++b)
        for (uint32_t p = a->first; p <= b->first; ++p) {
          const double z = a->second + (b->second - a->second) * double(p - a->first) /
                                           double(b->first - a->first);
          const uint32_t x = side < 2 ? p : side == 2 ? 0 : w - 1;
          const uint32_t y = side < 2 ? (side == 0 ? 0 : hh - 1) : p;
          worst = std::max(worst, std::abs(double(h(int32_t(x0 + x), int32_t(y0 + y))) - z));
        }
    }
  }
  return worst;
}

// Everything docs/format.md "VIPM tilesets" promises, checked on the file.
void expectValidVipmTileset(const std::string& path, const Heightfield& source, double maxError) {
  auto opened = TilesetReader::openFile(path);
  ASSERT_TRUE(opened.ok()) << opened.error().message;
  const TilesetReader& t = **opened;
  const TilesetHeader& hd = t.header();
  EXPECT_EQ(hd.version, 2u);
  EXPECT_TRUE(hd.textured());  // normal maps only
  EXPECT_EQ(hd.meshKind, MeshKind::kVipm);
  EXPECT_EQ(hd.levelCount, 2u);
  EXPECT_EQ(hd.leafCells, kVipmLeafCells);
  EXPECT_EQ(hd.rootCells, kVipmRootCells);
  EXPECT_EQ(hd.levelError[1], maxError);
  EXPECT_EQ(hd.leafError, maxError);
  const size_t materialCount = t.metadata().materials.size();
  EXPECT_GE(materialCount, 1u);
  EXPECT_NE(t.metadataJson().find("\"kind\": \"vipm\""), std::string::npos);
  const int32_t cellsX = int32_t(hd.sourceColumns) - 1, cellsY = int32_t(hd.sourceRows) - 1;

  std::vector<Chunk> chunks;
  for (uint32_t i = 0; i < t.nodes().size(); ++i) {
    const NodeRecord& n = t.nodes()[i];
    SCOPED_TRACE("node " + std::to_string(i));
    auto blob = t.readBlob(i);
    ASSERT_TRUE(blob.ok()) << blob.error().message;
    auto data = decodeVipmChunk(*blob, "node");
    ASSERT_TRUE(data.ok()) << data.error().message;
    Chunk c{*data, unpackChunk(*data)};
    auto levels = VipmLevels::reconstruct(c.unpacked.mesh, c.unpacked.materials);
    ASSERT_TRUE(levels.ok()) << levels.error().message;
    EXPECT_EQ(n.meshKind, MeshKind::kVipm);
    EXPECT_EQ(n.skirtTriangleCount, 0u);
    EXPECT_EQ(n.flags, kNodeHasTexture);
    // Its normal map: the source's central differences over the whole (unclipped) square.
    auto bytes = t.readNode(i);
    ASSERT_TRUE(bytes.ok()) << bytes.error().message;
    EXPECT_EQ(n.textureBytes, bytes->texture().size());
    auto normals = decodeVipmNormalMap(bytes->texture(), uint32_t(hd.chunkCells(n.level)), "node");
    ASSERT_TRUE(normals.ok()) << normals.error().message;
    EXPECT_EQ(normals->mips.size(), mipCount(normals->size));
    EXPECT_TRUE(normals->sourceLimited());
    EXPECT_EQ(std::vector<uint8_t>(bytes->texture().begin(), bytes->texture().end()),
              buildVipmNormalMap(source, int32_t(n.x) * hd.chunkCells(n.level),
                                 int32_t(n.y) * hd.chunkCells(n.level), hd.chunkCells(n.level),
                                 hd.spacingX, hd.spacingY));
    EXPECT_EQ(n.vertexCount, c.data.vertexCount());
    EXPECT_EQ(n.triangleCount, c.data.triangleCount());
    const int32_t side = hd.chunkCells(n.level);
    EXPECT_EQ(c.data.width, std::min(side, cellsX - int32_t(n.x) * side) + 1);
    EXPECT_EQ(c.data.height, std::min(side, cellsY - int32_t(n.y) * side) + 1);
    double lo = 1e300, hi = -1e300;
    for (const auto& p : c.unpacked.positions) {
      lo = std::min(lo, double(p[2]));
      hi = std::max(hi, double(p[2]));
    }
    EXPECT_EQ(n.minZ, floatBelow(lo));
    EXPECT_EQ(n.maxZ, floatAbove(hi));
    for (uint8_t m : c.data.materials) EXPECT_LT(m, materialCount);
    if (n.level == 1) {
      EXPECT_LE(c.data.finestError, maxError);
    } else if (c.data.collapseCount() > 0) {  // a blot root: it starts at the roots' level
      EXPECT_GE(c.unpacked.mesh.errors.front(), hd.levelError[0]);
    }
    EXPECT_EQ(c.data.zStep, chunks.empty() ? c.data.zStep : chunks.front().data.zStep);
    chunks.push_back(std::move(c));
  }

  // Roots' finest levels are their children's coarsest levels exactly; levelError[0] doubles
  // the worst.
  const size_t rootCount = size_t(hd.rootsX) * hd.rootsY;
  float largestCoarsest = 0.0f;
  std::map<std::pair<uint32_t, uint32_t>, double> deviation, rootDeviation, rootCoarsest;
  for (size_t r = 0; r < rootCount; ++r) {
    const NodeRecord& root = t.nodes()[r];
    SCOPED_TRACE("root " + std::to_string(r));
    std::vector<Triangle> joined, drawn;
    float childError = 0.0f;
    for (uint32_t c = root.firstChild; c < root.firstChild + std::popcount(root.childMask); ++c) {
      const NodeRecord& leaf = t.nodes()[c];
      const Chunk& k = chunks[c];
      auto levels = VipmLevels::reconstruct(k.unpacked.mesh, k.unpacked.materials);
      ASSERT_TRUE(levels.ok());
      levels->setApplied(levels->collapseCount());
      const auto& whole = levels->whole();
      const float error =
          k.unpacked.mesh.errors.empty() ? k.data.finestError : k.unpacked.mesh.errors.back();
      childError = std::max(childError, error);
      for (uint32_t i = 0; i < 3 * levels->drawnTriangles(whole); i += 3) {
        Triangle tri;
        for (int j = 0; j < 3; ++j) {
          const uint16_t v = whole.indices[i + j];
          const auto& p = k.unpacked.positions[v];
          tri[size_t(j)] = {leaf.x * 64 + uint32_t(p[0]), leaf.y * 64 + uint32_t(p[1]),
                            k.data.zBase + k.data.heights[v] * k.data.zStep, k.data.materials[v]};
        }
        joined.push_back(canonical(tri));
      }
      deviation[{leaf.x, leaf.y}] = bruteBorderDeviation(k, source, leaf.x * 64, leaf.y * 64);
    }
    const Chunk& k = chunks[r];
    for (uint32_t i = 0; i < k.data.indices.size(); i += 3) {
      Triangle tri;
      for (int j = 0; j < 3; ++j) {
        const uint16_t v = k.data.indices[i + j];
        const uint32_t p = k.data.points[v];
        tri[size_t(j)] = {root.x * 128 + p % k.data.width, root.y * 128 + p / k.data.width,
                          k.data.zBase + k.data.heights[v] * k.data.zStep, k.data.materials[v]};
      }
      drawn.push_back(canonical(tri));
    }
    std::sort(joined.begin(), joined.end());
    std::sort(drawn.begin(), drawn.end());
    EXPECT_EQ(drawn, joined);
    // Measured again over the root's own samples (from other corners: rounding apart).
    EXPECT_LE(k.data.finestError, childError * (1.0f + 1e-6f));
    largestCoarsest = std::max(largestCoarsest, childError);
    rootDeviation[{root.x, root.y}] = bruteBorderDeviation(k, source, root.x * 128, root.y * 128);
    const bool seams = k.data.width > 65 || k.data.height > 65;  // children side by side
    rootCoarsest[{root.x, root.y}] = !seams ? 0.0
                                     : k.unpacked.mesh.errors.empty()
                                         ? k.data.finestError
                                         : k.unpacked.mesh.errors.back();
  }
  EXPECT_EQ(hd.levelError[0], 2.0 * std::max(double(largestCoarsest), maxError));

  // Flanges: own deviation + the largest of any chunk that can be drawn beside it + zStep; a
  // root's also close its children's shared sides, if it has any (twice its coarsest error),
  // and are at least its children's.
  const double zStep = chunks.front().data.zStep;
  auto at = [](const auto& map, int64_t x, int64_t y) {
    const auto it = map.find({uint32_t(x), uint32_t(y)});
    return x < 0 || y < 0 || it == map.end() ? 0.0 : it->second;
  };
  static constexpr int64_t kDx[4] = {1, -1, 0, 0}, kDy[4] = {0, 0, 1, -1};
  std::map<std::pair<uint32_t, uint32_t>, double> leafDepth;
  for (const NodeRecord& n : t.nodes()) {
    if (n.level != 1) continue;
    double outside = 0.0;
    for (int k = 0; k < 4; ++k) {
      const int64_t x = n.x + kDx[k], y = n.y + kDy[k];
      outside = std::max(outside, at(deviation, x, y));
      if (x >> 1 != n.x >> 1 || y >> 1 != n.y >> 1)
        outside = std::max(outside, at(rootDeviation, x >> 1, y >> 1));
    }
    const double expected = at(deviation, n.x, n.y) + outside + zStep;
    EXPECT_NEAR(n.maxSkirtDepth, expected, 1e-4 * (1.0 + n.maxSkirtDepth));
    EXPECT_GE(double(n.maxSkirtDepth), expected - 1e-9);
    leafDepth[{n.x, n.y}] = n.maxSkirtDepth;
  }
  for (const NodeRecord& n : t.nodes()) {
    if (n.level != 0) continue;
    double outside = 0.0, children = 0.0;
    for (int k = 0; k < 4; ++k) {
      const int64_t x = n.x + kDx[k], y = n.y + kDy[k];
      outside = std::max(outside, at(rootDeviation, x, y));
      for (int q = 0; q < 4; ++q)
        outside = std::max(outside, at(deviation, 2 * x + (q & 1), 2 * y + (q >> 1)));
      children = std::max(children, at(leafDepth, 2 * n.x + (k & 1), 2 * n.y + (k >> 1)));
    }
    const double expected = std::max({at(rootDeviation, n.x, n.y) + outside + zStep,
                                      2.0 * at(rootCoarsest, n.x, n.y) + zStep, children});
    EXPECT_NEAR(n.maxSkirtDepth, expected, 1e-4 * (1.0 + n.maxSkirtDepth));
    EXPECT_GE(double(n.maxSkirtDepth), expected - 1e-6);
  }
}

// Normal maps (decoded from BC5) of a surface, one texel per grid point.
std::vector<uint8_t> decodedNormals(const Heightfield& h, int32_t x0, int32_t y0, int32_t cells) {
  auto layer = decodeVipmNormalMap(buildVipmNormalMap(h, x0, y0, cells, 10.0, 20.0),
                                   uint32_t(cells), "test");
  EXPECT_TRUE(layer.ok()) << layer.error().message;
  return layer.ok() ? decodeBc5Rg(layer->mips[0], layer->size) : std::vector<uint8_t>{};
}

TEST(VipmNormalMap, APlaneGivesItsNormalEverywhereIncludingTheEdges) {
  // z = 0.5 X - 0.25 Y (X, Y metres) over 10 m x 20 m cells: normal ∝ (-0.5, 0.25, 1).
  Heightfield h(100, 90);
  for (int32_t y = 0; y < 90; ++y)
    for (int32_t x = 0; x < 100; ++x) h(x, y) = float(0.5 * 10 * x - 0.25 * 20 * y);
  const double len = std::sqrt(0.5 * 0.5 + 0.25 * 0.25 + 1);
  const double ex = (-0.5 / len + 1) * 0.5 * 255, ey = (0.25 / len + 1) * 0.5 * 255;
  // Inside the data only: beyond it the nearest samples repeat (flat across the edge).
  const auto map = decodedNormals(h, 0, 0, 64);
  ASSERT_EQ(map.size(), size_t(65 * 65 * 2));
  for (int32_t y = 1; y < 65; ++y)
    for (int32_t x = 1; x < 65; ++x) {
      EXPECT_NEAR(map[size_t(y * 65 + x) * 2], ex, 1.0) << x << "," << y;
      EXPECT_NEAR(map[size_t(y * 65 + x) * 2 + 1], ey, 1.0) << x << "," << y;
    }
  // Flat ground faces straight up: x = y = 0 is the middle value.
  const auto flat = decodedNormals(Heightfield(70, 70, 3.0f), 0, 0, 64);
  for (uint8_t b : flat) EXPECT_NEAR(b, 127.5, 0.5);
}

TEST(VipmNormalMap, ARootAndItsChildrenStoreTheSameNormalsWhereTheyMeet) {
  // From the same full-resolution heights, whatever the meshes: a root's texel on a grid
  // point is its child's there (the same texels before compression; the same BC5 blocks but
  // for the children's last row and column, whose blocks hold repeats).
  const Heightfield h = sourceHeights(testData("crater_lake_0513.bt"));
  const int32_t bx = 192, by = 128;  // the crater's south-west rim
  const auto root = decodedNormals(h, bx, by, 128);
  ASSERT_EQ(root.size(), size_t(129 * 129 * 2));
  int differing = 0;
  for (int q = 0; q < 4; ++q) {
    const int32_t ox = 64 * (q & 1), oy = 64 * (q >> 1);
    const auto leaf = decodedNormals(h, bx + ox, by + oy, 64);
    ASSERT_EQ(leaf.size(), size_t(65 * 65 * 2));
    for (int32_t y = 0; y <= 64; ++y)
      for (int32_t x = 0; x <= 64; ++x)
        for (int c = 0; c < 2; ++c) {
          const int a = leaf[size_t(y * 65 + x) * 2 + size_t(c)];
          const int b = root[size_t((oy + y) * 129 + ox + x) * 2 + size_t(c)];
          if (x < 64 && y < 64) {
            EXPECT_EQ(a, b) << q << ": " << x << "," << y;
          }
          differing += a != b;  // only where the blocks differ (verify bounds those)
        }
  }
  EXPECT_LT(differing, 4 * 129 * 2);
  // And the leaves do not all store one map: the window is not flat.
  EXPECT_NE(decodedNormals(h, bx, by, 64), decodedNormals(h, bx + 64, by + 64, 64));
}

TEST(VipmBuilder, SynthTilesetIsAsDocumented) {
  TempDir dir;
  // 299 x 199 cells: leaves and roots clipped at the east and north edges.
  const std::string dem = synth(dir, 300, 200);
  const BuildSummary s = build(vipmOptions(dem, dir.file("s.tlod")));
  EXPECT_EQ(s.chunks, 6u + 20u);
  EXPECT_EQ(s.materials, 5u);
  expectValidVipmTileset(dir.file("s.tlod"), sourceHeights(dem), 1.0);
}

TEST(VipmBuilder, CraterLakeTilesetIsAsDocumented) {
  TempDir dir;
  const std::string dem =
      crop(testData("crater_lake_0513.bt"), dir.file("crater.tif"), 128, 160, 257, 193);
  BuildOptions o = vipmOptions(dem, dir.file("c.tlod"));
  o.maxError = 2.0;
  build(o);
  expectValidVipmTileset(o.output, sourceHeights(dem), 2.0);
}

TEST(VipmBuilder, ZionWithLandcoverMaterialsIsAsDocumented) {
  TempDir dir;
  const std::string dem =
      crop(testData("zion_srtm3_utm12_30m.tif"), dir.file("zion.tif"), 500, 600, 193, 193);
  BuildOptions o = vipmOptions(dem, dir.file("z.tlod"));
  o.materialsPath = testData("zion_landcover_classes.tif");
  o.palettePath = testData("zion_landcover_palette.json");
  const BuildSummary s = build(o);
  EXPECT_GE(s.materials, 2u);
  expectValidVipmTileset(o.output, sourceHeights(dem), 1.0);
  auto t = TilesetReader::openFile(o.output);
  ASSERT_TRUE(t.ok());
  const auto& materials = (*t)->metadata().materials;
  ASSERT_FALSE(materials.empty());
  EXPECT_EQ(materials.front().id, 1);  // the palette's names and colours
  EXPECT_EQ(materials.front().name, "vegetation");
  EXPECT_EQ(materials.front().color, (std::array<uint8_t, 3>{32, 42, 28}));
  EXPECT_NE((*t)->metadataJson().find("\"materials\": \"zion_landcover_classes.tif\""),
            std::string::npos);
}

TEST(VipmBuilder, OutputDoesNotDependOnThreadCount) {
  TempDir dir;
  const std::string dem = synth(dir, 200, 140);
  BuildOptions one = vipmOptions(dem, dir.file("one.tlod"));
  one.threads = 1;
  BuildOptions three = vipmOptions(dem, dir.file("three.tlod"));
  three.threads = 3;
  build(one);
  build(three);
  EXPECT_EQ(readWholeFile(one.output), readWholeFile(three.output));
}

TEST(VipmBuilder, NoMaterialRulesIsRecordedAndChangesTheMeshes) {
  TempDir dir;
  const std::string dem = synth(dir, 130, 130);
  BuildOptions on = vipmOptions(dem, dir.file("on.tlod"));
  BuildOptions off = vipmOptions(dem, dir.file("off.tlod"));
  off.materialRules = MaterialRules::kOff;
  build(on);
  build(off);
  expectValidVipmTileset(off.output, sourceHeights(dem), 1.0);
  const std::string a = readWholeFile(on.output), b = readWholeFile(off.output);
  EXPECT_NE(a, b);
  EXPECT_NE(a.find("\"material_rules\": true"), std::string::npos);
  EXPECT_NE(b.find("\"material_rules\": false"), std::string::npos);
}

TEST(VipmBuilder, RefusesOptionsThatDoNotApply) {
  TempDir dir;
  const std::string dem = synth(dir, 65, 65);
  BuildOptions o = vipmOptions(dem, dir.file("x.tlod"));
  o.textureImage = dem;
  NullProgress progress;
  auto s = buildTileset(o, progress, [](const std::string&) {});
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.error().message.find("--texture"), std::string::npos);
  EXPECT_FALSE(std::filesystem::exists(o.output));
}

}  // namespace
}  // namespace terralod
