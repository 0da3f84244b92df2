// `build --kind vipm --upper-levels`: the nodes above the 128-cell roots, checked from the file
// against the source. Each is its children's coarsest levels joined with their cracks closed
// (the same points, a manifold inside), its errors bound every source sample at its finest and
// coarsest levels, a level's error is twice the one below and at least its children's
// coarsest, and the top node simplifies to a few triangles.

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <filesystem>
#include <map>
#include <random>
#include <set>
#include <tuple>

#include "load_heights.h"
#include "temp_dir.h"
#include "terralod/build/builder.h"
#include "terralod/build/vipm_chunk_set.h"
#include "terralod/build/vipm_chunks.h"
#include "terralod/format/tileset_reader.h"
#include "terralod/format/vipm_chunk_codec.h"
#include "terralod/raster/void_fill.h"
#include "terralod/vipm/collapse_order.h"
#include "terralod/vipm/vipm_levels.h"
#include "terralod/vipm/vipm_storage.h"
#include "test_terrain.h"

namespace terralod {
namespace upper_levels_test {
namespace {

using test::TempDir;
using test::testData;

struct Node {
  NodeRecord record;
  VipmChunkData data;
  UnpackedChunk unpacked;
  int64_t x0 = 0, y0 = 0;  // south-west grid point
};

// A vertex as the world sees it: grid point and stored height.
using Vertex = std::tuple<int64_t, int64_t, double>;

Vertex vertexOf(const Node& n, uint32_t v) {
  return {n.x0 + n.data.points[v] % n.data.width, n.y0 + n.data.points[v] / n.data.width,
          n.data.zBase + double(n.data.heights[v]) * n.data.zStep};
}

// The triangles of a node's level after `applied` collapses (vertex indices).
std::vector<std::array<uint16_t, 3>> levelTriangles(const Node& n, uint32_t applied) {
  auto levels = VipmLevels::reconstruct(n.unpacked.mesh, n.unpacked.materials);
  EXPECT_TRUE(levels.ok());
  std::vector<std::array<uint16_t, 3>> out;
  if (!levels.ok()) return out;
  levels->setApplied(applied);
  const auto& whole = levels->whole();
  for (uint32_t i = 0; i < 3 * levels->drawnTriangles(whole); i += 3)
    out.push_back({whole.indices[i], whole.indices[i + 1], whole.indices[i + 2]});
  return out;
}

// The largest vertical distance between a level's triangles and the source samples they cover.
double trueError(const Node& n, const std::vector<std::array<uint16_t, 3>>& triangles,
                 const Heightfield& h) {
  double worst = 0.0;
  for (const auto& t : triangles) {
    double x[3], y[3], z[3];
    for (int k = 0; k < 3; ++k) {
      const auto [gx, gy, gz] = vertexOf(n, t[size_t(k)]);
      x[k] = double(gx);
      y[k] = double(gy);
      z[k] = gz;
    }
    const double d = (x[1] - x[0]) * (y[2] - y[0]) - (x[2] - x[0]) * (y[1] - y[0]);
    const auto [xa, xb] = std::minmax({x[0], x[1], x[2]});
    const auto [ya, yb] = std::minmax({y[0], y[1], y[2]});
    for (int64_t py = int64_t(ya); py <= int64_t(yb); ++py)
      for (int64_t px = int64_t(xa); px <= int64_t(xb); ++px) {
        const double l1 = ((px - x[0]) * (y[2] - y[0]) - (x[2] - x[0]) * (py - y[0])) / d;
        const double l2 = ((x[1] - x[0]) * (py - y[0]) - (px - x[0]) * (y[1] - y[0])) / d;
        const double l0 = 1 - l1 - l2;
        if (l0 < -1e-9 || l1 < -1e-9 || l2 < -1e-9) continue;
        const double z0 = l0 * z[0] + l1 * z[1] + l2 * z[2];
        worst = std::max(worst, std::abs(double(h(int32_t(px), int32_t(py))) - z0));
      }
  }
  return worst;
}

TEST(VipmUpperLevels, NodesAboveTheRootsJoinTheirChildrenAndBoundTheSource) {
  TempDir dir;
  BuildOptions o;
  o.input = testData("crater_lake_0513.bt");
  o.output = dir.file("c.tlod");
  o.kind = TilesetKind::kVipm;
  o.textures = false;
  o.threads = 2;
  o.maxError = 2.0;
  o.vipmUpperLevels =
      kVipmUpperLevelsAuto;  // 4 x 4 roots: two levels above them, one 512-cell top node
  NullProgress progress;
  auto built = buildTileset(o, progress, [](const std::string&) {});
  ASSERT_TRUE(built.ok()) << built.error().message;
  auto opened = TilesetReader::openFile(o.output);
  ASSERT_TRUE(opened.ok()) << opened.error().message;
  const TilesetReader& t = **opened;
  const TilesetHeader& hd = t.header();
  ASSERT_EQ(hd.levelCount, 4u);
  EXPECT_EQ(hd.rootCells, 512u);
  EXPECT_EQ(hd.rootsX * hd.rootsY, 1u);
  EXPECT_EQ(hd.levelError[3], 2.0);
  for (int level = 0; level < 2; ++level)
    EXPECT_EQ(hd.levelError[size_t(level)], 2.0 * hd.levelError[size_t(level) + 1]) << level;

  auto dem = DemReader::open(o.input, {});
  ASSERT_TRUE(dem.ok());
  auto heights = loadHeights(**dem, progress);
  ASSERT_TRUE(heights.ok());
  ASSERT_TRUE(fillVoids(*heights, o.input).ok());

  std::vector<Node> nodes;
  for (uint32_t i = 0; i < t.nodes().size(); ++i) {
    Node n;
    n.record = t.nodes()[i];
    auto blob = t.readBlob(i);
    ASSERT_TRUE(blob.ok()) << blob.error().message;
    auto data = decodeVipmChunk(*blob, "node");
    ASSERT_TRUE(data.ok()) << data.error().message;
    n.data = std::move(*data);
    n.unpacked = unpackChunk(n.data);
    const int64_t cells = hd.chunkCells(n.record.level);
    n.x0 = int64_t(n.record.x) * cells;
    n.y0 = int64_t(n.record.y) * cells;
    nodes.push_back(std::move(n));
  }
  auto coarsestError = [](const Node& n) {
    return n.unpacked.mesh.errors.empty() ? n.data.finestError : n.unpacked.mesh.errors.back();
  };
  for (size_t i = 0; i < nodes.size(); ++i) {
    const Node& n = nodes[i];
    if (n.record.level >= 2) continue;  // the roots and leaves: vipm_builder_test
    SCOPED_TRACE("node " + std::to_string(i) + " level " + std::to_string(n.record.level));
    EXPECT_EQ(vipmChunkVersion(n.data), 2);
    // Its finest level holds exactly its children's coarsest points.
    std::set<Vertex> own, children;
    for (uint32_t v = 0; v < n.data.vertexCount(); ++v) own.insert(vertexOf(n, v));
    for (uint32_t c = 0; c < uint32_t(std::popcount(n.record.childMask)); ++c) {
      const Node& child = nodes[n.record.firstChild + c];
      const auto coarsest = levelTriangles(child, child.data.collapseCount());
      for (const auto& tri : coarsest)
        for (uint16_t v : tri) children.insert(vertexOf(child, v));
      // A child draws its coarsest level where this node takes over: its last collapses
      // have finished geomorphing there (at kMorphSpan times their error), or the child
      // still slides where this node stands still and the merge pops (0.7-0.8 px on Crater
      // Lake's descent before).
      EXPECT_LE(coarsestError(child), hd.levelError[n.record.level]);
      if (!child.unpacked.mesh.errors.empty()) {
        EXPECT_LE(coarsestError(child) * kMorphSpan, hd.levelError[n.record.level] * (1.0 + 1e-6));
      }
    }
    EXPECT_EQ(own, children);
    // Its cracks are closed: every edge inside is shared by two triangles.
    const auto finest = levelTriangles(n, 0);
    std::map<std::pair<Vertex, Vertex>, int> edges;
    for (const auto& tri : finest)
      for (int k = 0; k < 3; ++k) {
        const Vertex a = vertexOf(n, tri[size_t(k)]), b = vertexOf(n, tri[size_t(k + 1) % 3]);
        ++edges[std::minmax(a, b)];
      }
    const int64_t x1 = n.x0 + n.data.width - 1, y1 = n.y0 + n.data.height - 1;
    int open = 0;
    for (const auto& [edge, uses] : edges) {
      const auto [ax, ay, az] = edge.first;
      const auto [bx, by, bz] = edge.second;
      const bool side =
          (ax == bx && (ax == n.x0 || ax == x1)) || (ay == by && (ay == n.y0 || ay == y1));
      if (!side) open += uses != 2;
    }
    EXPECT_EQ(open, 0);
    // Its recorded errors bound the source at its finest and coarsest levels.
    EXPECT_LE(trueError(n, finest, *heights), n.data.finestError * (1.0 + 1e-6));
    if (n.data.collapseCount() > 0) {
      EXPECT_GE(n.unpacked.mesh.errors.front(), hd.levelError[n.record.level]);
      EXPECT_LE(trueError(n, levelTriangles(n, n.data.collapseCount()), *heights),
                coarsestError(n) * (1.0 + 1e-6));
    }
    if (n.record.level == 1) {
      EXPECT_GT(n.data.collapseCount(), 0u);
      EXPECT_LE(coarsestError(n), hd.levelError[0]);
    }
  }
  // The top node ends with a few triangles.
  EXPECT_LT(levelTriangles(nodes[0], nodes[0].data.collapseCount()).size(),
            nodes[0].data.triangleCount() / 50);
}

}  // namespace
}  // namespace upper_levels_test
}  // namespace terralod

namespace terralod {
namespace {

// By default a map gets levels above its roots once it has more than kVipmFlatRootsMax of
// them; a smaller one stays a flat forest (all its roots resident).
TEST(VipmUpperLevels, ByDefaultOnlyMapsOfManyRootsGetLevelsAboveThem) {
  DemInfo info;
  info.columns = info.rows = 2049;  // 16 x 16 roots
  EXPECT_EQ(vipmTreeLayout(info, kVipmUpperLevelsBySize).depth, 1);
  EXPECT_EQ(vipmTreeLayout(info, kVipmUpperLevelsAuto).depth, 5);  // one 2048-cell top node
  info.columns = 2177;                                             // 17 x 16 roots
  EXPECT_EQ(vipmTreeLayout(info, kVipmUpperLevelsBySize).depth, 6);
  EXPECT_EQ(vipmTreeLayout(info, kVipmUpperLevelsBySize).rootsX, 1);
  EXPECT_EQ(vipmTreeLayout(info, 0).depth, 1);
  EXPECT_EQ(BuildOptions{}.vipmUpperLevels, kVipmUpperLevelsBySize);
}

// Terrain too rough to simplify (steps far above --max-error) keeps every point up to the
// roots, so a 256-cell node would join 257² points, more than a node can index. An explicit
// level count fails in one line and writes nothing; levels chosen by the map's size leave that
// level out, say so, and build.
TEST(VipmUpperLevels, NodesTooDenseToHoldAreLeftOutOrRefused) {
  test::TempDir dir;
  Heightfield noise(257, 257);
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  for (int32_t y = 0; y < 257; ++y)
    for (int32_t x = 0; x < 257; ++x)  // a checkerboard of 50 m steps, roughened
      noise(x, y) = 1000.0f + 50.0f * float((x + y) % 2) + 10.0f * unit(rng);
  test::writeGeoTiff(noise, dir.file("noise.tif"), 10.0);
  BuildOptions o;
  o.input = dir.file("noise.tif");
  o.kind = TilesetKind::kVipm;
  o.maxError = 0.05;
  o.threads = 2;
  NullProgress progress;
  std::vector<std::string> warnings;
  auto warn = [&](const std::string& line) { warnings.push_back(line); };

  o.output = dir.file("one.tlod");
  o.vipmUpperLevels = 1;
  auto refused = buildTileset(o, progress, warn);
  ASSERT_FALSE(refused.ok());
  EXPECT_NE(refused.error().message.find("noise.tif: its nodes of 256 cells would keep more than "
                                         "65536 vertices"),
            std::string::npos)
      << refused.error().message;
  EXPECT_NE(refused.error().message.find("--upper-levels 0 or fewer"), std::string::npos);
  EXPECT_FALSE(std::filesystem::exists(o.output));

  o.output = dir.file("auto.tlod");
  o.vipmUpperLevels = kVipmUpperLevelsAuto;
  auto built = buildTileset(o, progress, warn);
  ASSERT_TRUE(built.ok()) << built.error().message;
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("building with 0 levels above the roots instead"), std::string::npos)
      << warnings[0];
  auto tileset = TilesetReader::openFile(o.output);
  ASSERT_TRUE(tileset.ok()) << tileset.error().message;
  EXPECT_EQ((*tileset)->header().chunkCells(0), 128);  // a flat forest of 2 x 2 roots
  for (uint32_t i = 0; i < (*tileset)->nodes().size(); ++i) {
    auto bytes = (*tileset)->readNode(i);
    ASSERT_TRUE(bytes.ok());
    EXPECT_TRUE(decodeVipmChunk(bytes->mesh(), "node").ok()) << i;
  }
}

}  // namespace
}  // namespace terralod
