// What the VIPM chunk kind computes without GL: the allowed error θ and the flanges of the
// current border (its normal maps are stored: vipm_builder_test.cpp).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>

#include "terralod/vipm/vipm_flanges.h"
#include "terralod/vipm/vipm_levels.h"
#include "terralod/vipm/vipm_storage.h"
#include "terralod/vipm/vipm_theta.h"
#include "vipm_test_patches.h"

namespace terralod {
namespace {

TEST(VipmTheta, FollowsTheDistanceOnScheduleAndTheParentAtTheEndOfAnEasing) {
  const double own = 1.0, parent = 12.0;
  // On schedule t = (θ − δ_L) / (δ_{L−1} − δ_L), clamped: θ = τD/K everywhere.
  for (double allowance : {0.2, 1.0, 3.0, 11.9, 12.0, 40.0}) {
    const float t = float(std::clamp((allowance - own) / (parent - own), 0.0, 1.0));
    EXPECT_NEAR(vipmTheta(allowance, t, own, parent), std::max(allowance, own), 1e-6);
  }
  // A late split: t = 1 close by gives the parent's error (the leaf's coarsest level), and
  // easing down to the schedule lowers θ continuously to τD/K.
  EXPECT_EQ(vipmTheta(2.0, 1.0f, own, parent), parent);
  double last = parent;
  for (float t = 1.0f; t >= 0.0f; t -= 1.0f / 16.0f) {
    const double theta = vipmTheta(2.0, t, own, parent);
    EXPECT_LE(theta, last);
    EXPECT_GE(theta, 2.0);
    EXPECT_LE(last - theta, (parent - own) / 16.0 + 1e-9);
    last = theta;
  }
  EXPECT_EQ(vipmTheta(2.0, 0.0f, own, parent), 2.0);
}

TEST(VipmTheta, AtTheParentsErrorEveryCollapseIsApplied) {
  // The tileset's levelError[0] is twice the largest coarsest error: θ there applies all.
  GridPatch patch = test::demPatch("crater_lake_0513.bt", 192, 192, 1900, 2050, 65);
  const ProgressiveMesh mesh =
      makeProgressiveMesh(patch, buildCollapseOrder(patch, MaterialRules::kOn), 1.0);
  const double parent = 2.0 * mesh.errors.back();
  const MorphWindow w = morphWindow(mesh.errors, vipmTheta(0.5, 1.0f, 1.0, parent), Geomorph::kOn);
  EXPECT_EQ(w.applied, mesh.collapseCount());
  EXPECT_EQ(w.morphing, mesh.collapseCount());
}

// A chunk as stored and unpacked, from a window of Crater Lake.
UnpackedChunk storedChunk(int32_t size = 65) {
  GridPatch patch = test::demPatch("crater_lake_0513.bt", 100, 140, 1900, 2050, size);
  const HeightQuantisation q = chooseQuantisation(patch, 1.0);
  quantiseVertexHeights(patch, q);
  const ProgressiveMesh mesh =
      makeProgressiveMesh(patch, buildCollapseOrder(patch, MaterialRules::kOn), 1.0);
  return unpackChunk(packChunk(patch, mesh, q));
}

// The border polyline of side `bit` after `applied` collapses, straight from the mesh: the
// edges of living triangles with both ends on the side.
std::set<std::pair<uint16_t, uint16_t>> borderEdges(const UnpackedChunk& c, uint32_t applied,
                                                    bool (*on)(int32_t, int32_t, int32_t)) {
  auto levels = VipmLevels::reconstruct(c.mesh, c.materials);
  EXPECT_TRUE(levels.ok());
  levels->setApplied(applied);
  const int32_t w = c.mesh.width;
  std::set<std::pair<uint16_t, uint16_t>> edges;
  const VipmPart& whole = levels->whole();
  for (uint32_t t = 0; t < levels->drawnTriangles(whole); ++t)
    for (int k = 0; k < 3; ++k) {
      uint16_t a = whole.indices[3 * t + k], b = whole.indices[3 * t + (k + 1) % 3];
      if (on(c.mesh.points[a] % w, c.mesh.points[a] / w, w) &&
          on(c.mesh.points[b] % w, c.mesh.points[b] / w, w))
        edges.insert({std::min(a, b), std::max(a, b)});
    }
  return edges;
}

TEST(VipmFlanges, CloseEveryBorderEdgeOfTheCurrentLevelDownToTheCopies) {
  const UnpackedChunk c = storedChunk();
  const uint32_t n = c.mesh.vertexCount();
  const Flanges f = makeFlanges(c.mesh, kFlangeWest | kFlangeNorth);
  ASSERT_EQ(f.sides.size(), 2u);
  for (uint16_t top : f.tops) {
    const int32_t x = c.mesh.points[top] % 65, y = c.mesh.points[top] / 65;
    EXPECT_TRUE(x == 0 || y == 64);
  }
  auto west = [](int32_t x, int32_t, int32_t) { return x == 0; };
  auto north = [](int32_t, int32_t y, int32_t w) { return y == w - 1; };
  for (uint32_t applied : {0u, c.mesh.collapseCount() / 2, c.mesh.collapseCount()}) {
    std::vector<uint16_t> indices;
    flangeIndices(f, n, n - applied, {}, indices);
    ASSERT_EQ(indices.size() % 6, 0u);
    // Each pair of triangles spans one border edge (a, b) and the copies a', b' below it.
    std::set<std::pair<uint16_t, uint16_t>> spanned;
    for (size_t i = 0; i < indices.size(); i += 6) {
      const uint16_t a = indices[i], b = indices[i + 2];
      EXPECT_LT(a, n - applied);
      EXPECT_LT(b, n - applied);
      EXPECT_GE(indices[i + 1], n);
      EXPECT_EQ(f.tops[indices[i + 1] - n], b);
      EXPECT_EQ(f.tops[indices[i + 4] - n], a);
      spanned.insert({std::min(a, b), std::max(a, b)});
    }
    auto expect = borderEdges(c, applied, west);
    const auto northEdges = borderEdges(c, applied, north);
    expect.insert(northEdges.begin(), northEdges.end());
    EXPECT_EQ(spanned, expect) << applied;
  }
  // No sides, no flanges.
  std::vector<uint16_t> none;
  flangeIndices(makeFlanges(c.mesh, 0), n, n, {}, none);
  EXPECT_TRUE(none.empty());
}

// The flange edges on interior lines, as sets of top vertices.
std::multiset<std::set<uint16_t>> interiorEdgeTops(const std::vector<uint16_t>& indices) {
  std::multiset<std::set<uint16_t>> out;
  for (size_t i = 0; i < indices.size(); i += 6) out.insert({indices[i], indices[i + 2]});
  return out;
}

std::vector<uint16_t> flat(const std::vector<std::array<uint16_t, 3>>& triangles) {
  std::vector<uint16_t> out;
  for (const auto& t : triangles) out.insert(out.end(), t.begin(), t.end());
  return out;
}

TEST(VipmFlanges, ARootGetsFlangesUnderItsChildrensSharedSidesAtEveryLevel) {
  // Two squares side by side on a 129-point grid, sharing the line x = 64. The west one also
  // has vertex 6 at (64, 32) on it (a T-junction for the east one), which collapse 0 moves
  // onto vertex 1 along the line. Each triangle edge on the line gets a flange (one per side),
  // none elsewhere inside, and the flanges follow the level drawn.
  ProgressiveMesh m;
  m.width = 129;
  m.height = 65;
  for (int32_t y : {0, 64})
    for (int32_t x : {0, 64, 128}) m.points.push_back(uint16_t(y * 129 + x));
  m.points.push_back(uint16_t(32 * 129 + 64));
  m.targets = {1};
  m.errors = {1.0f};
  m.triangles = {{0, 6, 3}, {6, 4, 3}, {1, 2, 5}, {1, 5, 4}, {0, 1, 6}};
  const Flanges f = makeFlanges(m, 0, 64);
  EXPECT_TRUE(f.sides.empty());
  EXPECT_EQ(f.interiorEdgesMax, 3u);
  EXPECT_EQ(maxFlangeIndices(f), 18u);
  std::vector<uint16_t> indices;
  flangeIndices(f, m.vertexCount(), m.vertexCount(), flat(m.triangles), indices);
  using Tops = std::multiset<std::set<uint16_t>>;
  EXPECT_EQ(interiorEdgeTops(indices), (Tops{{1, 6}, {6, 4}, {1, 4}}));
  // Collapse 0 applied: vertex 6 is vertex 1, its triangle (0, 1, 6) gone.
  const std::vector<std::array<uint16_t, 3>> coarser = {{0, 1, 3}, {1, 4, 3}, {1, 2, 5}, {1, 5, 4}};
  flangeIndices(f, m.vertexCount(), m.vertexCount() - 1, flat(coarser), indices);
  EXPECT_EQ(interiorEdgeTops(indices), (Tops{{1, 4}, {1, 4}}));
  for (size_t i = 0; i < indices.size(); i += 6) {  // hanging from the copies of its own tops
    EXPECT_EQ(f.tops[indices[i + 1] - m.vertexCount()], indices[i + 2]);
    EXPECT_EQ(f.tops[indices[i + 4] - m.vertexCount()], indices[i]);
  }
  EXPECT_TRUE(makeFlanges(m, 0).interior.empty());
}

}  // namespace
}  // namespace terralod
