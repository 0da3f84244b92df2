// Fan stitching (vipm_fans.h) on a built VIPM tileset: for many cuts through its quadtree (a
// root drawn whole or as its four leaves), every chunk at its own level with its collapses
// geomorphing, the drawn triangles with the fans in place of the triangles they replace form
// one closed surface: every edge on a chunk border or a root's inner seam is met by the same
// edge the other way round, and the triangles cover the data exactly once. Without the fans
// they do not, and every border case the fans handle occurs here (counted), so leaving one out
// fails the test.

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <functional>
#include <map>
#include <random>
#include <tuple>

#include "temp_dir.h"
#include "terralod/build/builder.h"
#include "terralod/format/tileset_reader.h"
#include "terralod/vipm/vipm_blob.h"
#include "terralod/vipm/vipm_fans.h"

namespace terralod {
namespace {

using test::TempDir;
using test::testData;

struct LoadedNode {
  LoadedVipmChunk chunk;
  std::vector<std::array<float, 3>> own;
  StitchChunk where;
  VipmStitcher stitcher;
};

// Sliding points are rounded as coarsely as in a tileset of 32768-cell nodes (2^-8 cells),
// the case where a point most often lands on another's place or a span's end.
constexpr uint32_t kCoarsestRounding = 32768;

// A drawn chunk: its node, collapses applied and where its vertices are drawn.
struct Drawn {
  uint32_t node = 0;
  VipmLevels levels;
  std::vector<std::array<float, 3>> drawn;
};

using Point = std::tuple<double, double, double>;  // absolute grid x, y and metres

struct Cases {
  size_t fannedTriangles = 0;
  size_t twoLineTriangles = 0;  // a corner triangle fanned along two lines
  size_t seamFans = 0;          // fans on a root's inner seam
  size_t fractionalPoints = 0;  // inserted points off the grid (geomorphing)
  size_t rootLeafBorders = 0;   // fans where a root meets leaves
  size_t upperFans = 0;         // fans of nodes above the roots
};

class VipmStitch : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir = new TempDir;
    BuildOptions o;
    o.input = testData("crater_lake_0513.bt");
    o.output = dir->file("crater.tlod");
    o.kind = TilesetKind::kVipm;
    o.threads = 2;
    o.vipmUpperLevels = kVipmUpperLevelsAuto;  // 4 x 4 roots under two levels of nodes
    NullProgress progress;
    auto s = buildTileset(o, progress, [](const std::string&) {});
    ASSERT_TRUE(s.ok()) << s.error().message;
    auto opened = TilesetReader::openFile(o.output);
    ASSERT_TRUE(opened.ok()) << opened.error().message;
    tileset = opened->release();
    const TilesetHeader& h = tileset->header();
    for (uint32_t i = 0; i < tileset->nodes().size(); ++i) {
      const NodeRecord& r = tileset->nodes()[i];
      auto blob = tileset->readBlob(i);
      ASSERT_TRUE(blob.ok());
      const bool leaf = r.level + 1u == h.levelCount;
      auto chunk =
          loadVipmChunk(*blob, "node", leaf ? MaterialFade::kKeep : MaterialFade::kToTarget);
      ASSERT_TRUE(chunk.ok()) << chunk.error().message;
      LoadedNode n;
      n.chunk = std::move(chunk).value();
      n.own = positionsAboveBase(n.chunk);
      const int64_t cells = h.chunkCells(r.level);
      n.where = {int64_t(r.x) * cells,
                 int64_t(r.y) * cells,
                 n.chunk.data.zBase,
                 int32_t(n.chunk.data.width),
                 int32_t(n.chunk.data.height),
                 vipmSeamStep(uint32_t(cells)),
                 kCoarsestRounding};
      n.stitcher = VipmStitcher(n.chunk.unpacked.mesh, n.where);
      nodes.push_back(std::move(n));
    }
  }
  static void TearDownTestSuite() {
    nodes.clear();
    delete tileset;
    delete dir;
  }

  // A random cut: from the top, each node whole or as its children (more often above the
  // 128-cell roots), each at a random θ with geomorphing.
  static std::vector<Drawn> randomCut(std::mt19937& rng) {
    std::vector<Drawn> cut;
    const TilesetHeader& h = tileset->header();
    auto add = [&](uint32_t node) {
      const LoadedNode& n = nodes[node];
      const ProgressiveMesh& mesh = n.chunk.unpacked.mesh;
      Drawn d{node, n.chunk.levels, n.own};
      if (mesh.collapseCount() > 0) {
        const double lo = mesh.errors.front() * 0.9, hi = mesh.errors.back() * 1.3;
        const double theta = std::uniform_real_distribution<double>(lo, hi)(rng);
        const MorphWindow w = morphWindow(mesh.errors, theta, Geomorph::kOn);
        d.levels.setApplied(w.applied);
        morphPositions(mesh, w, theta, n.own, d.drawn);
        for (uint32_t j = w.applied; j < w.morphing; ++j)
          roundStitchPoint(d.drawn[mesh.vertexCount() - 1 - j], n.where);
      }
      cut.push_back(std::move(d));
    };
    std::function<void(uint32_t)> visit = [&](uint32_t i) {
      const NodeRecord& n = tileset->nodes()[i];
      const bool upper = n.level + 2u < h.levelCount;
      if (n.childMask == 0 || rng() % (upper ? 4 : 2) == 0) {
        add(i);
      } else {
        for (uint32_t c = n.firstChild; c < n.firstChild + std::popcount(n.childMask); ++c)
          visit(c);
      }
    };
    for (uint32_t r = 0; r < h.rootsX * h.rootsY; ++r) visit(r);
    return cut;
  }

  // The cut's triangles in absolute coordinates, with the fans (or without: `fans` false).
  static std::vector<std::array<Point, 3>> surface(std::vector<Drawn>& cut, bool fans,
                                                   Cases& cases) {
    StitchTable table;
    std::vector<std::array<uint8_t, kMaxMaterials>> weights;
    for (const Drawn& d : cut) {
      const LoadedNode& n = nodes[d.node];
      weights.assign(d.drawn.size(), {});
      n.stitcher.addPoints(table, d.levels.activeVertices(), d.drawn, weights,
                           n.chunk.unpacked.materials);
    }
    table.finish();
    std::vector<std::array<Point, 3>> out;
    StitchFans f;
    for (const Drawn& d : cut) {
      const LoadedNode& n = nodes[d.node];
      const VipmPart& whole = d.levels.whole();
      const auto living =
          std::span(whole.indices).first(size_t(d.levels.drawnTriangles(whole)) * 3);
      f.clear();
      if (fans) n.stitcher.fan(table, living, d.drawn, f);
      auto absolute = [&](uint32_t v) {
        const auto& p = v < d.drawn.size() ? d.drawn[v] : f.positions[v - d.drawn.size()];
        return Point{double(n.where.cornerX) + double(p[0]), double(n.where.cornerY) + double(p[1]),
                     n.where.zBase + double(p[2])};
      };
      size_t next = 0;
      for (size_t t = 0; t < living.size() / 3; ++t) {
        if (next < f.replaced.size() && f.replaced[next] == t) {
          ++next;
          continue;
        }
        out.push_back(
            {absolute(living[3 * t]), absolute(living[3 * t + 1]), absolute(living[3 * t + 2])});
      }
      for (const auto& tri : f.triangles)
        out.push_back({absolute(tri[0]), absolute(tri[1]), absolute(tri[2])});
      // The cases met.
      cases.fannedTriangles += f.replaced.size();
      for (const auto& p : f.positions)
        if (p[0] != std::floor(p[0]) || p[1] != std::floor(p[1])) ++cases.fractionalPoints;
      const NodeRecord& r = tileset->nodes()[d.node];
      for (uint32_t t : f.replaced) {
        int lines = 0, seams = 0, leafSides = 0;
        for (int e = 0; e < 3; ++e) {
          const Point a = absolute(living[3 * t + e]), b = absolute(living[3 * t + (e + 1) % 3]);
          for (int axis = 0; axis < 2; ++axis) {
            const double ca = axis == 0 ? std::get<0>(a) : std::get<1>(a);
            const double cb = axis == 0 ? std::get<0>(b) : std::get<1>(b);
            if (ca != cb || std::fmod(ca, double(kStitchLineCells)) != 0.0) continue;
            const double along0 = axis == 0 ? std::get<1>(a) : std::get<0>(a);
            const double along1 = axis == 0 ? std::get<1>(b) : std::get<0>(b);
            bool reversed = false;
            if (table
                    .between({uint8_t(axis), int64_t(ca)}, along0, std::get<2>(a), along1,
                             std::get<2>(b), reversed)
                    .empty())
              continue;
            ++lines;
            const double local = ca - double(axis == 0 ? n.where.cornerX : n.where.cornerY);
            const bool root = r.level + 2u == tileset->header().levelCount;
            if (root && local == double(kStitchLineCells)) ++seams;
            if (root && (local == 0.0 || local == double(kVipmRootCells))) ++leafSides;
            if (r.level + 2u < tileset->header().levelCount) ++cases.upperFans;
          }
        }
        if (lines >= 2) ++cases.twoLineTriangles;
        cases.seamFans += size_t(seams);
        cases.rootLeafBorders += size_t(leafSides);
      }
    }
    return out;
  }

  static TempDir* dir;
  static TilesetReader* tileset;
  static std::vector<LoadedNode> nodes;
};
TempDir* VipmStitch::dir = nullptr;
TilesetReader* VipmStitch::tileset = nullptr;
std::vector<LoadedNode> VipmStitch::nodes;

// Edges on stitch lines inside the data that no edge the other way round meets, and the
// area the triangles cover (signed, seen from above; grid cells²).
struct Closure {
  size_t unmatched = 0;
  double area = 0.0;
  double negativeArea = 0.0;
};
Closure closure(const std::vector<std::array<Point, 3>>& triangles, double cellsX, double cellsY) {
  std::map<std::pair<Point, Point>, int> edges;
  Closure c;
  auto onInnerLine = [&](const Point& p, const Point& q) {
    for (int axis = 0; axis < 2; ++axis) {
      const double a = axis == 0 ? std::get<0>(p) : std::get<1>(p);
      const double b = axis == 0 ? std::get<0>(q) : std::get<1>(q);
      const double end = axis == 0 ? cellsX : cellsY;
      if (a == b && std::fmod(a, double(kStitchLineCells)) == 0.0 && a > 0.0 && a < end)
        return true;
    }
    return false;
  };
  for (const auto& t : triangles) {
    const double ax = std::get<0>(t[1]) - std::get<0>(t[0]),
                 ay = std::get<1>(t[1]) - std::get<1>(t[0]);
    const double bx = std::get<0>(t[2]) - std::get<0>(t[0]),
                 by = std::get<1>(t[2]) - std::get<1>(t[0]);
    const double area = 0.5 * (ax * by - ay * bx);
    c.area += area;
    if (area < -1e-9) c.negativeArea -= area;
    for (int e = 0; e < 3; ++e) {
      const Point& p = t[size_t(e)];
      const Point& q = t[size_t((e + 1) % 3)];
      // Zero length: a vertex geomorphed onto its target's place (to the rounding); its
      // triangle is empty.
      if (!onInnerLine(p, q) || p == q) continue;
      // An edge p -> q cancels a q -> p.
      auto back = edges.find({q, p});
      if (back != edges.end() && back->second > 0) {
        if (--back->second == 0) edges.erase(back);
      } else {
        ++edges[{p, q}];
      }
    }
  }
  for (const auto& [edge, count] : edges) c.unmatched += size_t(count);
  return c;
}

TEST_F(VipmStitch, EveryCutIsOneClosedSurfaceWithFansAndNotWithout) {
  const TilesetHeader& h = tileset->header();
  const double cellsX = double(h.sourceColumns - 1), cellsY = double(h.sourceRows - 1);
  std::mt19937 rng(20261204);
  Cases cases;
  size_t unmatchedWithout = 0;
  for (int cut = 0; cut < 24; ++cut) {
    SCOPED_TRACE("cut " + std::to_string(cut));
    std::vector<Drawn> drawn = randomCut(rng);
    const Closure with = closure(surface(drawn, true, cases), cellsX, cellsY);
    EXPECT_EQ(with.unmatched, 0u);
    EXPECT_NEAR(with.area, cellsX * cellsY, 1e-6 * cellsX * cellsY);
    // Nothing turned over but slivers dying under a geomorph (a vertex rounded to 2^-8 cells
    // a hair from its target's place).
    EXPECT_LT(with.negativeArea, 1e-3);
    Cases ignored;
    unmatchedWithout += closure(surface(drawn, false, ignored), cellsX, cellsY).unmatched;
  }
  EXPECT_GT(unmatchedWithout, 100u);
  // Every case the fans handle was met.
  EXPECT_GT(cases.fannedTriangles, 100u);
  EXPECT_GT(cases.twoLineTriangles, 0u);
  EXPECT_GT(cases.seamFans, 0u);
  EXPECT_GT(cases.fractionalPoints, 0u);
  EXPECT_GT(cases.rootLeafBorders, 0u);
  EXPECT_GT(cases.upperFans, 0u);
  std::printf("fanned %zu, two lines %zu, seams %zu, sliding points %zu, root-leaf %zu\n",
              cases.fannedTriangles, cases.twoLineTriangles, cases.seamFans, cases.fractionalPoints,
              cases.rootLeafBorders);
}

TEST_F(VipmStitch, FansStayWithinTheirBounds) {
  std::mt19937 rng(7);
  for (int cut = 0; cut < 8; ++cut) {
    std::vector<Drawn> drawn = randomCut(rng);
    StitchTable table;
    std::vector<std::array<uint8_t, kMaxMaterials>> weights;
    for (const Drawn& d : drawn) {
      weights.assign(d.drawn.size(), {});
      nodes[d.node].stitcher.addPoints(table, d.levels.activeVertices(), d.drawn, weights,
                                       nodes[d.node].chunk.unpacked.materials);
    }
    table.finish();
    for (const Drawn& d : drawn) {
      const VipmStitcher& s = nodes[d.node].stitcher;
      StitchFans f;
      const VipmPart& whole = d.levels.whole();
      s.fan(table, std::span(whole.indices).first(size_t(d.levels.drawnTriangles(whole)) * 3),
            d.drawn, f);
      EXPECT_LE(f.triangles.size(), s.maxFanTriangles());
      EXPECT_LE(f.positions.size(), s.maxInsertedPoints());
    }
  }
}

}  // namespace
}  // namespace terralod
