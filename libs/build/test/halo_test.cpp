// The cluster build's reduce holds only the blocks' halos; finishing the borders there must give
// every point the activation the whole-grid reduce of a local build gives it.

#include "terralod/build/halo.h"

#include <gtest/gtest.h>

#include "block_stages.h"
#include "terralod/build/activation_pass.h"
#include "test_terrain.h"

namespace terralod {
namespace {

struct HaloCase {
  int32_t columns, rows, leaf, block;
  uint32_t seed;
  double maxError;
};

class HaloReduce : public ::testing::TestWithParam<HaloCase> {};

TEST_P(HaloReduce, EqualsTheWholeGridReduce) {
  const HaloCase c = GetParam();
  const Heightfield h = test::makeTestTerrain(c.columns, c.rows, c.seed);
  MemoryHeights heights(h);
  const TreeLayout layout = makeTreeLayout(c.columns, c.rows, c.leaf).value();
  float lo = h.values()[0], hi = lo;
  for (float v : h.values()) lo = std::min(lo, v), hi = std::max(hi, v);
  const ErrorBudget budget = makeErrorBudget(layout, c.maxError, hi - lo).value();
  ActivationOptions options;
  options.blockCells = c.block;
  NullProgress progress;
  const ActivationGrid whole =
      computeActivations(layout, budget, heights, heights, options, progress).value();

  HaloStore store(layout, c.block);
  std::vector<Pass1Block> blocks;
  std::vector<BlockSquare> squares;
  BlockScratch scratch;
  std::vector<float> window(size_t(c.block + 1) * (c.block + 1));
  for (size_t b = 0; b < store.blockCount(); ++b) {
    const GridPoint o = store.origin(b);
    ASSERT_TRUE(heights.read(o.x, o.y, c.block + 1, c.block + 1, window.data(), 0));
    blocks.push_back(pass1Block(layout, budget, o, c.block, window.data(), scratch));
    store.values(b) = haloValues(blocks.back().grid, store.pattern(b));
    squares.push_back(blocks.back().square);
  }
  store.mergeBorders();
  finishBorders(layout, budget, heights, store, c.block, squares);
  EXPECT_EQ(store.misses(), 0u);

  size_t changed = 0, haloPoints = 0;
  for (size_t b = 0; b < store.blockCount(); ++b) {
    ActivationGrid& w = blocks[b].grid;
    const auto before = w.nibbles();
    applyHalo(w, store.pattern(b), store.values(b));
    changed += before != w.nibbles();
    haloPoints += store.pattern(b).points.size();
    const GridPoint o = store.origin(b);
    for (int32_t y = o.y; y <= o.y + c.block; ++y)
      for (int32_t x = o.x; x <= o.x + c.block; ++x)
        ASSERT_EQ(w.get(x, y), whole.get(x, y)) << "block " << b << " point " << x << "," << y;
  }
  EXPECT_GT(changed, 0u) << "the reduce changed nothing: the case does not test it";
  // A band along the borders, not the whole square.
  EXPECT_LT(double(haloPoints), 0.5 * double(store.blockCount()) * (c.block + 1) * (c.block + 1));
}

INSTANTIATE_TEST_SUITE_P(Terrains, HaloReduce,
                         ::testing::Values(HaloCase{257, 257, 16, 64, 3, 1.0},
                                           HaloCase{300, 200, 16, 32, 4, 0.5},
                                           HaloCase{129, 400, 8, 16, 5, 2.0},
                                           HaloCase{513, 513, 32, 128, 6, 1.0}));

TEST(Halo, IsABandAlongTheBorders) {
  const TreeLayout layout = makeTreeLayout(4097, 4097, 64).value();
  const HaloPattern halo = haloOf(layout, {1024, 512}, 512);
  // Every border point, and a few points per border point inside.
  EXPECT_GE(halo.points.size(), size_t(4 * 512));
  EXPECT_LT(halo.points.size(), size_t(16 * 512));
  // The block's centre (a parent of its border midpoints) is in it.
  EXPECT_TRUE(std::binary_search(halo.points.begin(), halo.points.end(), 256u * 513u + 256u));
}

}  // namespace
}  // namespace terralod
