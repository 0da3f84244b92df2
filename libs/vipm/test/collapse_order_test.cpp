#include "terralod/vipm/collapse_order.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>
#include <vector>

#include "patch_mesh.h"
#include "terralod/vipm/progressive_mesh.h"
#include "vipm_test_patches.h"

namespace terralod {
namespace {

using Tri = std::array<uint16_t, 3>;

int64_t area2(const GridPatch& p, const Tri& t) {
  const int64_t ax = p.xOf(t[0]), ay = p.yOf(t[0]), bx = p.xOf(t[1]), by = p.yOf(t[1]);
  const int64_t cx = p.xOf(t[2]), cy = p.yOf(t[2]);
  return (bx - ax) * (cy - ay) - (cx - ax) * (by - ay);
}

// Replays the first `count` collapses of `order` naively (corners renamed, degenerate
// triangles dropped).
std::vector<Tri> meshAfter(const CollapseOrder& order, size_t count, uint32_t points) {
  std::vector<uint16_t> to = test::unrenamed(points);
  for (size_t k = 0; k < count; ++k) to[order.collapses[k].vertex] = order.collapses[k].target;
  return test::renamed(order.gridTriangles, to);
}

// Brute force: for every sample, the vertical distance to each triangle covering it, and the
// material weights there.
struct Oracle {
  double error = 0;
  bool everySampleCovered = true;
};
Oracle bruteForce(const GridPatch& p, const std::vector<Tri>& tris) {
  Oracle o;
  for (int32_t y = 0; y < p.height; ++y) {
    for (int32_t x = 0; x < p.width; ++x) {
      bool covered = false;
      for (const Tri& t : tris) {
        double px[3], py[3], pz[3];
        for (int i = 0; i < 3; ++i) {
          px[i] = p.xOf(t[i]);
          py[i] = p.yOf(t[i]);
          pz[i] = p.vertexHeight(t[i]);
        }
        const double d = (px[1] - px[0]) * (py[2] - py[0]) - (px[2] - px[0]) * (py[1] - py[0]);
        const double l1 = ((x - px[0]) * (py[2] - py[0]) - (px[2] - px[0]) * (y - py[0])) / d;
        const double l2 = ((px[1] - px[0]) * (y - py[0]) - (x - px[0]) * (py[1] - py[0])) / d;
        const double l0 = 1 - l1 - l2;
        if (l0 < -1e-9 || l1 < -1e-9 || l2 < -1e-9) continue;
        covered = true;
        const double z = l0 * pz[0] + l1 * pz[1] + l2 * pz[2];
        o.error = std::max(o.error, std::abs(z - p.heightAt(x, y)));
      }
      if (!covered) o.everySampleCovered = false;
    }
  }
  return o;
}

TEST(GridTriangulation, CoversTheCellsCounterClockwise) {
  GridPatch p = test::wavyPatch(5, 4);
  const auto tris = gridTriangulation(5, 4);
  ASSERT_EQ(tris.size(), size_t(2 * 4 * 3));
  int64_t total = 0;
  for (const Tri& t : tris) {
    EXPECT_EQ(area2(p, t), 1);
    total += area2(p, t);
  }
  EXPECT_EQ(total, 2 * 4 * 3);
}

TEST(TriangleError, MatchesTheBruteForceOnARealWindow) {
  const GridPatch p = test::demPatch("crater_lake_0513.bt", 100, 300, 1800, 2000, 17);
  // A big triangle across the window and its brute-force error.
  const Tri t{p.id(0, 0), p.id(16, 3), p.id(5, 16)};
  const double scanned = triangleError(p, t[0], t[1], t[2]);
  EXPECT_NEAR(scanned, bruteForce(p, {t}).error, 1e-9);
  EXPECT_GT(scanned, 1.0);
  // The early stop returns something above the limit.
  EXPECT_GT(triangleError(p, t[0], t[1], t[2], scanned / 2), scanned / 2);
}

TEST(CollapseOrder, AFlatPatchCollapsesToItsCornersAtNoError) {
  GridPatch p;
  p.width = p.height = 9;
  p.heights.assign(81, 5.0f);
  p.materials.assign(81, 0);
  const CollapseOrder order = buildCollapseOrder(p, MaterialRules::kOn);
  EXPECT_EQ(order.collapses.size(), 81u - 4u);
  for (const Collapse& c : order.collapses) EXPECT_EQ(c.error, 0.0f);
  const auto last = meshAfter(order, order.collapses.size(), 81);
  EXPECT_EQ(last.size(), 2u);
}

class RealChunk : public ::testing::TestWithParam<MaterialRules> {};

// Every few collapses: errors never decrease and bound the true error; the mesh covers the
// square with counter-clockwise triangles; corners stay; side vertices move along their side.
TEST_P(RealChunk, ErrorsBoundTheSurfaceAndTheBorderHolds) {
  const GridPatch p = test::demPatch("crater_lake_0513.bt", 192, 192, 1900, 2050, 33);
  const CollapseOrder order = buildCollapseOrder(p, GetParam());
  ASSERT_GT(order.collapses.size(), 500u);
  float previous = 0;
  for (const Collapse& c : order.collapses) {
    EXPECT_GE(c.error, previous);
    previous = c.error;
    const int32_t vx = p.xOf(c.vertex), vy = p.yOf(c.vertex);
    const int32_t ux = p.xOf(c.target), uy = p.yOf(c.target);
    const bool vOnX = vx == 0 || vx == p.width - 1, vOnY = vy == 0 || vy == p.height - 1;
    EXPECT_FALSE(vOnX && vOnY) << "a corner moved";
    if (vOnX) {
      EXPECT_EQ(ux, vx);
    }
    if (vOnY) {
      EXPECT_EQ(uy, vy);
    }
  }
  for (size_t k : {size_t(0), size_t(50), order.collapses.size() / 2, order.collapses.size() - 1,
                   order.collapses.size()}) {
    const auto tris = meshAfter(order, k, p.pointCount());
    int64_t total = 0;
    for (const Tri& t : tris) {
      EXPECT_GT(area2(p, t), 0);
      total += area2(p, t);
    }
    EXPECT_EQ(total, 2 * int64_t(p.width - 1) * (p.height - 1)) << "after " << k;
    const Oracle o = bruteForce(p, tris);
    EXPECT_TRUE(o.everySampleCovered);
    const double recorded = k == 0 ? 0.0 : order.collapses[k - 1].error;
    EXPECT_LE(o.error, recorded + 1e-6) << "after " << k << " collapses";
  }
}

INSTANTIATE_TEST_SUITE_P(Rules, RealChunk,
                         ::testing::Values(MaterialRules::kOn, MaterialRules::kOff));

// An order can start from a given mesh (a fallback root's children's coarsest levels joined,
// the first step to the far field): only its vertices collapse, the errors start at its own,
// still bound the surface, and vertices on the seams move along them.
TEST(CollapseOrder, StartsFromAGivenMeshAndKeepsSeamVerticesOnTheirSeams) {
  const GridPatch p = test::demPatch("crater_lake_0513.bt", 192, 192, 1900, 2050, 33);
  const CollapseOrder first = buildCollapseOrder(p, MaterialRules::kOn);
  size_t applied = 0;  // the first order's level at 2 m
  while (applied < first.collapses.size() && first.collapses[applied].error <= 2.0f) ++applied;
  ASSERT_GT(applied, 100u);
  CollapseStart start;
  start.triangles = meshAfter(first, applied, p.pointCount());
  start.seamX = 16;
  start.seamY = 16;
  std::vector<uint8_t> used(p.pointCount(), 0);
  for (const Tri& t : start.triangles)
    for (uint16_t v : t) used[v] = 1;
  const CollapseOrder order = buildCollapseOrder(p, MaterialRules::kOff, start);
  ASSERT_GT(order.collapses.size(), 50u);
  EXPECT_GT(order.startError, 0.0f);
  // (Up to rounding: the error is measured from another corner of each triangle.)
  EXPECT_LE(order.startError, first.collapses[applied - 1].error * (1.0f + 1e-6f));
  std::vector<uint8_t> removed(p.pointCount(), 0);
  float previous = order.startError;
  for (const Collapse& c : order.collapses) {
    EXPECT_TRUE(used[c.vertex] && used[c.target]) << "a point outside the start moved";
    EXPECT_FALSE(removed[c.vertex]);
    removed[c.vertex] = 1;
    EXPECT_GE(c.error, previous);
    previous = c.error;
    const int32_t vx = p.xOf(c.vertex), vy = p.yOf(c.vertex);
    const int32_t ux = p.xOf(c.target), uy = p.yOf(c.target);
    const bool onX = vx == 0 || vx == 16 || vx == p.width - 1;
    const bool onY = vy == 0 || vy == 16 || vy == p.height - 1;
    EXPECT_FALSE(onX && onY) << "a corner or a seam's end moved: " << vx << "," << vy;
    if (onX) {
      EXPECT_EQ(ux, vx);
    }
    if (onY) {
      EXPECT_EQ(uy, vy);
    }
  }
  for (size_t k : {size_t(0), order.collapses.size() / 2, order.collapses.size()}) {
    std::vector<uint16_t> to = test::unrenamed(p.pointCount());
    for (size_t j = 0; j < k; ++j) to[order.collapses[j].vertex] = order.collapses[j].target;
    const auto tris = test::renamed(start.triangles, to);
    int64_t total = 0;
    for (const Tri& t : tris) total += area2(p, t);
    EXPECT_EQ(total, 2 * int64_t(p.width - 1) * (p.height - 1)) << "after " << k;
    const Oracle o = bruteForce(p, tris);
    const double recorded = k == 0 ? order.startError : order.collapses[k - 1].error;
    EXPECT_LE(o.error, recorded + 1e-6) << "after " << k << " collapses";
  }
  // The progressive mesh holds the start's vertices only, and starts at its error.
  const ProgressiveMesh mesh = makeProgressiveMesh(p, order, 0.0);
  EXPECT_EQ(mesh.vertexCount(), uint32_t(std::count(used.begin(), used.end(), 1)));
  EXPECT_EQ(mesh.finestError, order.startError);
  EXPECT_TRUE(triangleRemovals(mesh).ok());
}

// The sparse form of a dense patch (a node above the roots is one): its points the ones `used`
// marks, in grid order, and its samples bounded over blocks of `step` x `step` points.
struct SparseOf {
  GridPatch patch;
  std::vector<uint16_t> denseId;   // per sparse point
  std::vector<uint16_t> sparseId;  // per dense point (used ones)
};
SparseOf sparseOf(const GridPatch& dense, const std::vector<uint8_t>& used, int32_t step) {
  SparseOf s;
  s.patch.width = dense.width;
  s.patch.height = dense.height;
  s.sparseId.assign(dense.pointCount(), UINT16_MAX);
  for (uint32_t v = 0; v < dense.pointCount(); ++v) {
    if (!used[v]) continue;
    s.sparseId[v] = uint16_t(s.denseId.size());
    s.denseId.push_back(uint16_t(v));
    s.patch.pointX.push_back(dense.xOf(v));
    s.patch.pointY.push_back(dense.yOf(v));
    s.patch.heights.push_back(dense.heights[v]);
    s.patch.materials.push_back(dense.materials[v]);
  }
  s.patch.samples = makeSampleBlocks(dense.width, dense.height, step,
                                     [&](int32_t x, int32_t y) { return dense.heightAt(x, y); });
  return s;
}

// A root's start on the Crater Lake window: the first order's level at 2 m, seams at 16.
struct SeamedStart {
  GridPatch patch;
  CollapseStart start;
  std::vector<uint8_t> used;
};
SeamedStart seamedStart() {
  SeamedStart s;
  s.patch = test::demPatch("crater_lake_0513.bt", 192, 192, 1900, 2050, 33);
  const CollapseOrder first = buildCollapseOrder(s.patch, MaterialRules::kOn);
  size_t applied = 0;
  while (applied < first.collapses.size() && first.collapses[applied].error <= 2.0f) ++applied;
  s.start.triangles = meshAfter(first, applied, s.patch.pointCount());
  s.start.seamX = s.start.seamY = 16;
  s.used.assign(s.patch.pointCount(), 0);
  for (const Tri& t : s.start.triangles)
    for (uint16_t v : t) s.used[v] = 1;
  return s;
}

CollapseStart sparseStart(const CollapseStart& dense, const SparseOf& s) {
  CollapseStart out = dense;
  for (Tri& t : out.triangles)
    for (uint16_t& v : t) v = s.sparseId[v];
  return out;
}

// With single-sample blocks a sparse patch is the dense one by other names: the same order.
TEST(CollapseOrder, ASparsePatchOfSingleSamplesCollapsesAsTheDenseOne) {
  const SeamedStart d = seamedStart();
  const SparseOf s = sparseOf(d.patch, d.used, 1);
  const CollapseOrder dense = buildCollapseOrder(d.patch, MaterialRules::kOff, d.start);
  const CollapseOrder sparse =
      buildCollapseOrder(s.patch, MaterialRules::kOff, sparseStart(d.start, s));
  ASSERT_GT(dense.collapses.size(), 50u);
  EXPECT_EQ(sparse.startError, dense.startError);
  ASSERT_EQ(sparse.collapses.size(), dense.collapses.size());
  for (size_t k = 0; k < dense.collapses.size(); ++k) {
    EXPECT_EQ(s.denseId[sparse.collapses[k].vertex], dense.collapses[k].vertex) << k;
    EXPECT_EQ(s.denseId[sparse.collapses[k].target], dense.collapses[k].target) << k;
    EXPECT_EQ(sparse.collapses[k].error, dense.collapses[k].error) << k;
  }
  // Its progressive mesh names grid points, as the dense one's does.
  const ProgressiveMesh a = makeProgressiveMesh(d.patch, dense, 0.0);
  const ProgressiveMesh b = makeProgressiveMesh(s.patch, sparse, 0.0);
  EXPECT_EQ(a.points, b.points);
  EXPECT_EQ(a.triangles, b.triangles);
}

// Over coarser blocks the errors are bounds: every level's recorded error holds against every
// sample, and they are looser than the exact ones (the blocks are alive).
TEST(CollapseOrder, ASparsePatchsBlockErrorsBoundEverySample) {
  const SeamedStart d = seamedStart();
  const SparseOf s = sparseOf(d.patch, d.used, 4);
  const CollapseOrder exact = buildCollapseOrder(d.patch, MaterialRules::kOff, d.start);
  const CollapseOrder order =
      buildCollapseOrder(s.patch, MaterialRules::kOff, sparseStart(d.start, s));
  ASSERT_GT(order.collapses.size(), 50u);
  EXPECT_GT(order.startError, exact.startError);
  for (size_t k : {size_t(0), size_t(10), order.collapses.size() / 2, order.collapses.size()}) {
    std::vector<uint16_t> to = test::unrenamed(d.patch.pointCount());
    for (size_t j = 0; j < k; ++j)
      to[s.denseId[order.collapses[j].vertex]] = s.denseId[order.collapses[j].target];
    const Oracle o = bruteForce(d.patch, test::renamed(d.start.triangles, to));
    const double recorded = k == 0 ? order.startError : order.collapses[k - 1].error;
    EXPECT_LE(o.error, recorded + 1e-6) << "after " << k << " collapses";
    EXPECT_TRUE(o.everySampleCovered);
  }
}

// The three material rules hold for every collapse with them, and the first fails without
// them (so the test can tell).
TEST(CollapseOrder, MaterialRulesHoldAndAreAlive) {
  const GridPatch p = test::demPatch("crater_lake_0513.bt", 192, 192, 1900, 2050, 65);
  auto check = [&](MaterialRules rules) {
    const CollapseOrder order = buildCollapseOrder(p, rules);
    size_t crossMaterial = 0, boundaryToInterior = 0, interpolationChanged = 0;
    std::vector<uint16_t> to = test::unrenamed(p.pointCount());
    auto tris = meshAfter(order, 0, p.pointCount());
    for (const Collapse& c : order.collapses) {
      auto onBoundary = [&](uint16_t v) {
        for (const Tri& t : tris)
          if (std::find(t.begin(), t.end(), v) != t.end())
            for (uint16_t w : t)
              if (p.materials[w] != p.materials[v]) return true;
        return false;
      };
      if (p.materials[c.vertex] != p.materials[c.target]) ++crossMaterial;
      if (onBoundary(c.vertex) && !onBoundary(c.target)) ++boundaryToInterior;
      to[c.vertex] = c.target;
      tris = test::renamed(tris, to);
      // Interpolated material at the removed vertex's position.
      const double x = p.xOf(c.vertex), y = p.yOf(c.vertex);
      for (const Tri& t : tris) {
        double px[3], py[3];
        for (int i = 0; i < 3; ++i) px[i] = p.xOf(t[i]), py[i] = p.yOf(t[i]);
        const double d = (px[1] - px[0]) * (py[2] - py[0]) - (px[2] - px[0]) * (py[1] - py[0]);
        const double l[3] = {
            1 - ((x - px[0]) * (py[2] - py[0]) - (px[2] - px[0]) * (y - py[0])) / d -
                ((px[1] - px[0]) * (y - py[0]) - (x - px[0]) * (py[1] - py[0])) / d,
            ((x - px[0]) * (py[2] - py[0]) - (px[2] - px[0]) * (y - py[0])) / d,
            ((px[1] - px[0]) * (y - py[0]) - (x - px[0]) * (py[1] - py[0])) / d};
        if (l[0] < -1e-9 || l[1] < -1e-9 || l[2] < -1e-9) continue;
        for (int i = 0; i < 3; ++i)
          if (l[i] > 1e-9 && p.materials[t[i]] != p.materials[c.vertex]) ++interpolationChanged;
      }
    }
    return std::array<size_t, 3>{crossMaterial, boundaryToInterior, interpolationChanged};
  };
  const auto with = check(MaterialRules::kOn);
  EXPECT_EQ(with[0], 0u);
  EXPECT_EQ(with[1], 0u);
  EXPECT_EQ(with[2], 0u);
  const auto without = check(MaterialRules::kOff);
  EXPECT_GT(without[0], 10u);
  EXPECT_GT(without[2], 10u);
}

}  // namespace
}  // namespace terralod
