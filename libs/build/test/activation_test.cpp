#include "terralod/build/activation_pass.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <random>

#include "terralod/core/bintree.h"
#include "test_terrain.h"
#include "triangle_scan.h"

namespace terralod {
namespace {

// Brute force: exact error of every diamond triangle over the data samples it covers, then
// saturation over the dependency order (finest first).
ActivationGrid referenceActivations(const Heightfield& h, const TreeLayout& layout,
                                    const ErrorBudget& budget) {
  const int32_t side = layout.gridSide();
  ActivationGrid grid(layout.gridX(), layout.gridY());
  auto height = [&](GridPoint p) { return double(h.at(p.x, p.y)); };
  auto exactError = [&](const BinTriangle& t) {
    const double area = double(orient2d(t.a, t.b, t.apex));
    double e = 0;
    for (int32_t y = std::min({t.a.y, t.b.y, t.apex.y}); y <= std::max({t.a.y, t.b.y, t.apex.y});
         ++y)
      for (int32_t x = std::min({t.a.x, t.b.x, t.apex.x}); x <= std::max({t.a.x, t.b.x, t.apex.x});
           ++x) {
        if (x > layout.cellsX || y > layout.cellsY) continue;
        const GridPoint p{x, y};
        const double wa = double(orient2d(t.b, t.apex, p)) / area;
        const double wb = double(orient2d(t.apex, t.a, p)) / area;
        const double wc = double(orient2d(t.a, t.b, p)) / area;
        if (wa < 0 || wb < 0 || wc < 0) continue;
        const double plane = wa * height(t.a) + wb * height(t.b) + wc * height(t.apex);
        e = std::max(e, std::fabs(double(h.at(x, y)) - plane));
      }
    return e;
  };
  struct Entry {
    int key;
    GridPoint v;
    VertexClass c;
  };
  std::vector<Entry> order;
  for (int32_t y = 0; y <= layout.gridY(); ++y)
    for (int32_t x = 0; x <= layout.gridX(); ++x) {
      const VertexClass c = classifyVertex(x, y, side);
      if (c.kind == VertexKind::kCorner || c.half >= layout.rootCells) continue;
      const int key =
          2 * std::countr_zero(uint32_t(c.half)) + (c.kind == VertexKind::kSquareCenter ? 1 : 0);
      order.push_back({key, {x, y}, c});
    }
  std::stable_sort(order.begin(), order.end(),
                   [](const Entry& a, const Entry& b) { return a.key < b.key; });
  for (const Entry& e : order) {
    const auto tris = diamondTriangles(e.v, e.c);
    const bool rising = e.c.kind == VertexKind::kSquareCenter &&
                        squareHasRisingDiagonal(e.v.x - e.c.half, e.v.y - e.c.half, 2 * e.c.half);
    uint8_t a = 0;
    for (int s = 0; s < 2; ++s) {
      if (!insideGrid(tris[s], layout.gridX(), layout.gridY())) continue;
      a = std::max(a, budget.activation(exactError(tris[s])));
      if (e.c.kind == VertexKind::kEdgeMidpoint && e.c.half < 2) continue;
      for (const ChildSlot& k : childSlots(e.c, rising, s))
        a = std::max(a, grid.get(e.v.x + k.dx, e.v.y + k.dy));
    }
    grid.set(e.v.x, e.v.y, a);
  }
  return grid;
}

struct Case {
  int32_t columns, rows, leafCells, blockCells;
  double leafError;
  uint32_t seed;
};

class ActivationMatchesBruteForce : public ::testing::TestWithParam<Case> {};

TEST_P(ActivationMatchesBruteForce, ExactInsideBlocksConservativeAbove) {
  const Case c = GetParam();
  const Heightfield h = test::makeTestTerrain(c.columns, c.rows, c.seed);
  const TreeLayout layout = makeTreeLayout(c.columns, c.rows, c.leafCells).value();
  const ErrorBudget budget = makeErrorBudget(layout, c.leafError, 400.0).value();
  MemoryHeights heights(h);
  NullProgress progress;
  ActivationOptions options;
  options.blockCells = c.blockCells;
  options.threads = 2;
  ActivationStats stats;
  const ActivationGrid grid =
      computeActivations(layout, budget, heights, heights, options, progress, &stats).value();
  const ActivationGrid reference = referenceActivations(h, layout, budget);
  const int32_t block = std::clamp(c.blockCells, layout.leafCells, layout.rootCells);
  int higher = 0, nonzero = 0;
  for (int32_t y = 0; y <= layout.gridY(); ++y)
    for (int32_t x = 0; x <= layout.gridX(); ++x) {
      const VertexClass vc = classifyVertex(x, y, layout.gridSide());
      if (vc.kind == VertexKind::kCorner || vc.half >= layout.rootCells) continue;
      const uint8_t got = grid.get(x, y), want = reference.get(x, y);
      nonzero += want > 0;
      // Diamonds larger than a block use the children's bound and may only be higher.
      const bool coarse = (vc.kind == VertexKind::kEdgeMidpoint && vc.half >= block) ||
                          (vc.kind == VertexKind::kSquareCenter && vc.half >= block);
      if (coarse) {
        ASSERT_GE(got, want) << x << "," << y;
        higher += got > want;
      } else {
        ASSERT_EQ(got, want) << "at " << x << "," << y << " half " << vc.half;
      }
    }
  EXPECT_GT(nonzero, 100);  // the terrain exercises the thresholds
  EXPECT_GT(stats.trianglesBounded, 0u);
  if (c.columns >= 97) {  // tiny noisy grids saturate first
    EXPECT_GT(stats.trianglesScanned, 0u);
  }
  if (block == layout.rootCells) {
    EXPECT_EQ(higher, 0);
  }
}

// The branch-free sides give the scalar formula's floats: never below the exact sum, and
// the nearest float at or above it.
TEST(TriangleBound, RoundUpSidesIsTheScalarRounding) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> offset(-50.0, 50.0), base(0.0, 20.0);
  std::uniform_int_distribution<int> pick(0, 5);
  int roundedUp = 0;
  for (int i = 0; i < 200000; ++i) {
    double d = offset(rng);
    double ba = pick(rng) == 0 ? 0.0 : double(float(base(rng)));
    double bb = pick(rng) == 0 ? 0.0 : double(float(base(rng)));
    if (pick(rng) == 0) d = double(float(d));  // exactly representable sums
    if (i < 3) d = i == 0 ? 0.0 : (i == 1 ? -0.0 : 1e-300);
    const TriangleErrorBounds got = roundUpSides(d, ba, bb);
    const float wantAbove = roundUp(ba + std::max(0.0, d));
    const float wantBelow = roundUp(bb + std::max(0.0, -d));
    ASSERT_EQ(std::bit_cast<uint32_t>(got.above), std::bit_cast<uint32_t>(wantAbove)) << d;
    ASSERT_EQ(std::bit_cast<uint32_t>(got.below), std::bit_cast<uint32_t>(wantBelow)) << d;
    ASSERT_GE(double(got.above), ba + std::max(0.0, d));
    ASSERT_GE(double(got.below), bb + std::max(0.0, -d));
    roundedUp += double(got.above) > ba + std::max(0.0, d);
  }
  EXPECT_GT(roundedUp, 1000);  // the rounding step is exercised
}

INSTANTIATE_TEST_SUITE_P(
    Terrains, ActivationMatchesBruteForce,
    ::testing::Values(Case{65, 65, 16, 64, 1.0, 1}, Case{129, 129, 16, 128, 0.5, 2},
                      Case{97, 65, 16, 16, 1.0, 3},  // several blocks, padding, coarse pass
                      Case{130, 47, 8, 32, 2.0, 4},  // forest of roots, not 2^n+1
                      Case{257, 200, 16, 32, 1.0, 5}));

}  // namespace
}  // namespace terralod
