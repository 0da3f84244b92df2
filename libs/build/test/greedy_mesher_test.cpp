// The greedy-insertion chunk mesher: every sample within its bound, no holes, counter-clockwise
// triangles, far fewer than the samples on smooth ground; it refines its parent (exactly, or
// within the gap it is given), keeps its children's borders, and shared sides match.

#include "terralod/build/greedy_mesher.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <set>

namespace terralod {
namespace {

// Rolling hills with a ridge and a little roughness (deterministic).
double terrain(int32_t x, int32_t y) {
  const double fx = x * 0.07, fy = y * 0.05;
  return 40.0 * std::sin(fx) * std::cos(fy) + 25.0 * std::exp(-0.002 * (x - y) * (x - y)) +
         0.2 * std::sin(x * 1.9 + y * 3.1);
}

std::vector<double> grid(int32_t x0, int32_t y0, int32_t w, int32_t h) {
  std::vector<double> out;
  for (int32_t y = 0; y <= h; ++y)
    for (int32_t x = 0; x <= w; ++x) out.push_back(terrain(x0 + x, y0 + y));
  return out;
}

// The rectangle as two triangles (a parent with nothing inside).
std::vector<SurfaceCorner> square(int32_t x0, int32_t y0, int32_t side) {
  return {{x0, y0, 0}, {x0 + side, y0, 0},        {x0 + side, y0 + side, 0},
          {x0, y0, 0}, {x0 + side, y0 + side, 0}, {x0, y0 + side, 0}};
}

// A chunk without a morph gap: its parent's edges stay.
GreedyMeshInput nested(int32_t w, int32_t h, const std::vector<double>& heights,
                       const std::vector<SurfaceCorner>& parent, int32_t lines, double error) {
  GreedyMeshInput in;
  in.width = w;
  in.height = h;
  in.heights = heights;
  in.parent = parent;
  in.lineSpacing = lines;
  in.error = error;
  return in;
}

double area2(const GreedyMesh& m, size_t k) {
  const uint32_t a = m.triangles[k], b = m.triangles[k + 1], c = m.triangles[k + 2];
  return double(m.x[b] - m.x[a]) * (m.y[c] - m.y[a]) - double(m.y[b] - m.y[a]) * (m.x[c] - m.x[a]);
}

// A mesh's triangles with the given heights at their corners (sample coordinates).
std::vector<SurfaceCorner> cornersOf(const GreedyMesh& m, const std::vector<double>& heights,
                                     int32_t stride, int32_t dx = 0, int32_t dy = 0) {
  std::vector<SurfaceCorner> out;
  for (const uint32_t v : m.triangles)
    out.push_back({m.x[v] + dx, m.y[v] + dy, heights[size_t(m.y[v]) * stride + m.x[v]]});
  return out;
}

// A mesh's triangles with its own vertex heights.
std::vector<SurfaceCorner> cornersOf(const GreedyMesh& m) {
  std::vector<SurfaceCorner> out;
  for (const uint32_t v : m.triangles) out.push_back({m.x[v], m.y[v], m.z[v]});
  return out;
}

// A surface's heights at every sample of [0, w] x [0, h] (corners in the same coordinates).
std::vector<double> rasterize(const std::vector<SurfaceCorner>& corners, int32_t w, int32_t h) {
  std::vector<double> out(size_t(w + 1) * (h + 1), std::nan(""));
  for (size_t k = 0; k + 2 < corners.size(); k += 3) {
    const SurfaceCorner tri[3] = {corners[k], corners[k + 1], corners[k + 2]};
    rasterizeTriangle(tri, 0, 0, w, h,
                      [&](int32_t x, int32_t y, double z) { out[size_t(y) * (w + 1) + x] = z; });
  }
  return out;
}

TEST(GreedyMesher, HoldsItsBoundWithFewTrianglesAndCoversTheRectangle) {
  const std::vector<double> h = grid(0, 0, 64, 48);
  const std::vector<SurfaceCorner> parent = {{0, 0, 0}, {64, 0, 0},  {64, 48, 0},
                                             {0, 0, 0}, {64, 48, 0}, {0, 48, 0}};
  GreedyMeshInput in = nested(64, 48, h, parent, 0, 0.5);
  const GreedyMesh m = greedyMesh(in);
  EXPECT_LE(greedyMeshViolation(in, m), 1e-9);
  double area = 0;
  for (size_t k = 0; k < m.triangles.size(); k += 3) {
    ASSERT_GT(area2(m, k), 0.0) << "triangle " << k / 3;
    area += area2(m, k);
  }
  EXPECT_DOUBLE_EQ(area, 2.0 * 64 * 48);  // covered (no holes above), so no overlaps
  const size_t triangles = m.triangles.size() / 3;
  EXPECT_GT(triangles, 20u);
  EXPECT_LT(triangles, 64u * 48u / 2u);
  // A looser bound needs fewer triangles; a bound of zero needs every sample.
  in.error = 2.0;
  EXPECT_LT(greedyMesh(in).triangles.size() / 3, triangles);
  in.error = 0.0;
  const GreedyMesh exact = greedyMesh(in);
  EXPECT_EQ(exact.x.size(), 65u * 49u);
  EXPECT_LE(greedyMeshViolation(in, exact), 0.0);
}

// A 64-cell parent's surface over its south-west 32-cell quarter, at every sample.
std::vector<double> southWestQuarter(const std::vector<SurfaceCorner>& parentCorners) {
  const std::vector<double> parentSurface = rasterize(parentCorners, 64, 64);
  std::vector<double> out;
  for (int32_t y = 0; y <= 32; ++y)
    for (int32_t x = 0; x <= 32; ++x) out.push_back(parentSurface[size_t(y) * 65 + x]);
  return out;
}

TEST(GreedyMesher, RefinesItsParentAndKeepsItsChildrensBorders) {
  // A 64-cell parent meshed at 2 m with lines every 32 cells; its south-west child (32 cells)
  // at 1 m from the parent's triangles in that quarter.
  const std::vector<double> h = grid(0, 0, 64, 64);
  const std::vector<SurfaceCorner> rect = square(0, 0, 64);
  const GreedyMesh parent = greedyMesh(nested(64, 64, h, rect, 32, 2.0));
  ASSERT_FALSE(parent.triangles.empty());
  for (size_t k = 0; k < parent.triangles.size(); k += 3) {
    // No triangle crosses x = 32 or y = 32.
    int32_t lo[2] = {64, 64}, hi[2] = {0, 0};
    for (int i = 0; i < 3; ++i) {
      const uint32_t v = parent.triangles[k + size_t(i)];
      lo[0] = std::min(lo[0], parent.x[v]), hi[0] = std::max(hi[0], parent.x[v]);
      lo[1] = std::min(lo[1], parent.y[v]), hi[1] = std::max(hi[1], parent.y[v]);
    }
    EXPECT_FALSE(lo[0] < 32 && hi[0] > 32) << "triangle " << k / 3 << " crosses x = 32";
    EXPECT_FALSE(lo[1] < 32 && hi[1] > 32) << "triangle " << k / 3 << " crosses y = 32";
  }
  const std::vector<SurfaceCorner> parentCorners = cornersOf(parent);
  // The child's own heights and the parent's surface over its quarter.
  const std::vector<double> childHeights = grid(0, 0, 32, 32);
  const std::vector<double> childParent = southWestQuarter(parentCorners);
  const GreedyMesh exact = greedyMesh(nested(32, 32, childHeights, parentCorners, 0, 1.0));
  ASSERT_FALSE(exact.triangles.empty());
  EXPECT_LE(greedyMeshViolation(nested(32, 32, childHeights, parentCorners, 0, 1.0), exact), 1e-9);
  // Its vertices on the parent's surface draw the parent's surface exactly.
  const std::vector<double> morphed = rasterize(cornersOf(exact, childParent, 33), 32, 32);
  double gap = 0;
  for (size_t s = 0; s < morphed.size(); ++s)
    gap = std::max(gap, std::fabs(morphed[s] - childParent[s]));
  EXPECT_LT(gap, 1e-9);
  // With a gap allowed, it keeps to it and needs fewer triangles.
  const GreedyMesh loose =
      greedyMesh({32, 32, childHeights, parentCorners, 0, 1.0, childParent, 0.25, 2.0});
  EXPECT_LE(greedyMeshViolation(nested(32, 32, childHeights, parentCorners, 0, 1.0), loose), 1e-9);
  const std::vector<double> looseMorphed = rasterize(cornersOf(loose, childParent, 33), 32, 32);
  double looseGap = 0;
  for (size_t s = 0; s < looseMorphed.size(); ++s)
    looseGap = std::max(looseGap, std::fabs(looseMorphed[s] - childParent[s]));
  EXPECT_LE(looseGap, 0.25 + 1e-9);
  EXPECT_GT(looseGap, 1e-6);  // it used the gap
  EXPECT_LT(loose.triangles.size(), exact.triangles.size());
}

// A parent meshed without lines crosses its children's borders off the grid: a child cannot
// start from its triangles, but it can start from its vertices (GreedyStart::kParentVertices,
// and with the parent's edges inside it, kParentVerticesAndEdges), and then holds its bound and
// keeps to the gap at every sample all the same.
TEST(GreedyMesher, StartsFromItsParentsVertices) {
  const std::vector<double> h = grid(0, 0, 64, 64);
  const GreedyMesh parent = greedyMesh(nested(64, 64, h, square(0, 0, 64), 0, 2.0));
  ASSERT_FALSE(parent.triangles.empty());
  const std::vector<SurfaceCorner> parentCorners = cornersOf(parent);
  const std::vector<double> childHeights = grid(0, 0, 32, 32);
  const std::vector<double> childParent = southWestQuarter(parentCorners);
  GreedyMeshInput in{32, 32, childHeights, parentCorners, 0, 1.0, childParent, 0.25, 2.0};
  EXPECT_TRUE(greedyMesh(in).triangles.empty()) << "the parent's triangles cut along the grid";
  for (const GreedyStart start :
       {GreedyStart::kParentVertices, GreedyStart::kParentVerticesAndEdges}) {
    SCOPED_TRACE(start == GreedyStart::kParentVertices ? "vertices" : "vertices and edges");
    in.start = start;
    const GreedyMesh child = greedyMesh(in);
    ASSERT_FALSE(child.triangles.empty());
    for (size_t k = 0; k < child.triangles.size(); k += 3) EXPECT_GT(area2(child, k), 0.0);
    EXPECT_LE(greedyMeshViolation(in, child), 1e-9);
    // Every parent vertex in the quarter is one of the child's.
    std::set<std::pair<int32_t, int32_t>> vertices;
    for (size_t v = 0; v < child.x.size(); ++v) vertices.insert({child.x[v], child.y[v]});
    for (const SurfaceCorner& c : parentCorners) {
      if (c.x <= 32 && c.y <= 32) {
        EXPECT_TRUE(vertices.count({c.x, c.y})) << "parent vertex (" << c.x << ", " << c.y << ")";
      }
    }
    // Its vertices on the parent's surface draw it within the gap, which it used.
    const std::vector<double> morphed = rasterize(cornersOf(child, childParent, 33), 32, 32);
    double gap = 0;
    for (size_t s = 0; s < morphed.size(); ++s)
      gap = std::max(gap, std::fabs(morphed[s] - childParent[s]));
    EXPECT_LE(gap, 0.25 + 1e-9);
    EXPECT_GT(gap, 1e-6);
  }
}

TEST(GreedyMesher, NeighboursShareTheirCommonSidesVertices) {
  // Two 40 x 40 rectangles side by side, sharing the line x = 40.
  const std::vector<double> left = grid(0, 0, 40, 40), right = grid(40, 0, 40, 40);
  const std::vector<SurfaceCorner> rect = square(0, 0, 40);
  const GreedyMesh l = greedyMesh(nested(40, 40, left, rect, 0, 0.3));
  const GreedyMesh r = greedyMesh(nested(40, 40, right, rect, 0, 0.3));
  std::set<int32_t> onLeft, onRight;
  for (size_t i = 0; i < l.x.size(); ++i)
    if (l.x[i] == 40) onLeft.insert(l.y[i]);
  for (size_t i = 0; i < r.x.size(); ++i)
    if (r.x[i] == 0) onRight.insert(r.y[i]);
  EXPECT_GT(onLeft.size(), 2u);
  EXPECT_EQ(onLeft, onRight);
  // At the same heights: their samples'.
  for (size_t i = 0; i < l.x.size(); ++i) {
    if (l.x[i] == 40) {
      EXPECT_EQ(l.z[i], left[size_t(l.y[i]) * 41 + 40]) << "y = " << l.y[i];
    }
  }
  for (size_t i = 0; i < r.x.size(); ++i) {
    if (r.x[i] == 0) {
      EXPECT_EQ(r.z[i], right[size_t(r.y[i]) * 41]) << "y = " << r.y[i];
    }
  }
}

TEST(GreedyMesher, FittedHeightsNeedFewerTriangles) {
  const std::vector<double> h = grid(0, 0, 64, 64);
  const std::vector<SurfaceCorner> rect = square(0, 0, 64);
  GreedyMeshInput in = nested(64, 64, h, rect, 0, 0.5);
  in.vertexHeights = VertexHeights::kSamples;
  const GreedyMesh samples = greedyMesh(in);
  in.vertexHeights = VertexHeights::kFitted;
  const GreedyMesh fitted = greedyMesh(in);
  EXPECT_LE(greedyMeshViolation(in, samples), 1e-9);
  EXPECT_LE(greedyMeshViolation(in, fitted), 1e-9);
  EXPECT_LT(double(fitted.triangles.size()), 0.9 * double(samples.triangles.size()));
  size_t moved = 0;
  for (size_t i = 0; i < samples.x.size(); ++i)
    EXPECT_EQ(samples.z[i], h[size_t(samples.y[i]) * 65 + samples.x[i]]);
  for (size_t i = 0; i < fitted.x.size(); ++i) {
    const double sampleHeight = h[size_t(fitted.y[i]) * 65 + fitted.x[i]];
    const bool onSide =
        fitted.x[i] == 0 || fitted.y[i] == 0 || fitted.x[i] == 64 || fitted.y[i] == 64;
    if (onSide) {
      EXPECT_EQ(fitted.z[i], sampleHeight);
    }
    moved += fitted.z[i] != sampleHeight ? 1 : 0;
  }
  EXPECT_GT(moved, fitted.x.size() / 4);
}

TEST(GreedyMesher, RefusesAParentThatCrossesALineOffTheGrid) {
  const std::vector<double> h = grid(0, 0, 8, 8);
  // An edge from (0, 0) to (8, 3) crosses x = 4 at y = 1.5.
  const std::vector<SurfaceCorner> parent = {{0, 0, 0}, {8, 3, 0}, {0, 8, 0}, {0, 0, 0}, {8, 0, 0},
                                             {8, 3, 0}, {0, 8, 0}, {8, 3, 0}, {8, 8, 0}};
  EXPECT_TRUE(greedyMesh(nested(8, 8, h, parent, 4, 0.1)).triangles.empty());
  EXPECT_FALSE(greedyMesh(nested(8, 8, h, parent, 0, 0.1)).triangles.empty());
}

}  // namespace
}  // namespace terralod
