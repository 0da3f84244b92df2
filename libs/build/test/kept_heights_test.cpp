// KeptHeights: the one halo pattern it keeps is every block's (what haloOf gives for each
// origin); it answers exactly the points it kept, misses counted for the others; and over its
// budget it keeps no block.

#include "terralod/build/kept_heights.h"

#include <gtest/gtest.h>

#include <cmath>
#include <initializer_list>
#include <vector>

#include "terralod/build/halo.h"
#include "terralod/build/tree_layout.h"

namespace terralod {
namespace {

struct KeptLayoutCase {
  int32_t columns, rows, leafCells, block;
};

TEST(KeptHeights, OneHaloServesEveryBlock) {
  for (const KeptLayoutCase c :
       {KeptLayoutCase{301, 211, 16, 32}, KeptLayoutCase{1025, 1025, 64, 256},
        KeptLayoutCase{129, 77, 16, 64}, KeptLayoutCase{2049, 700, 128, 512},
        KeptLayoutCase{513, 513, 16, 512}}) {
    const TreeLayout layout = makeTreeLayout(c.columns, c.rows, c.leafCells).value();
    const KeptHeights kept(layout, c.block, uint64_t{1} << 30);
    for (int32_t oy = 0; oy + c.block <= layout.gridY(); oy += c.block)
      for (int32_t ox = 0; ox + c.block <= layout.gridX(); ox += c.block)
        ASSERT_EQ(kept.halo(), haloOf(layout, {ox, oy}, c.block))
            << c.columns << "x" << c.rows << " block " << c.block << " at " << ox << "," << oy;
  }
}

// Gives every store every block of the data, the height at (x, y) being 1000 x + y.
void keepEveryBlock(const TreeLayout& layout, int32_t block, const ActivationGrid& grid,
                    std::initializer_list<KeptHeights*> stores) {
  std::vector<float> window(size_t(block + 1) * (block + 1));
  for (int32_t oy = 0; oy < layout.cellsY; oy += block)
    for (int32_t ox = 0; ox < layout.cellsX; ox += block) {
      for (int32_t ly = 0; ly <= block; ++ly)
        for (int32_t lx = 0; lx <= block; ++lx)
          window[size_t(ly) * (block + 1) + lx] = float((ox + lx) * 1000 + oy + ly);
      for (KeptHeights* kept : stores) kept->keepBlock({ox, oy}, window.data(), grid);
    }
}

TEST(KeptHeights, AnswersWhatItKeptAndCountsTheRest) {
  const TreeLayout layout = makeTreeLayout(100, 70, 16).value();  // cells 99 x 69
  const int32_t block = 32;
  KeptHeights kept(layout, block, uint64_t{1} << 30);
  KeptHeights tight(layout, block, 5000);  // room for a few blocks, not twelve
  ActivationGrid grid(layout.gridX(), layout.gridY());
  grid.set(5, 7, 3);  // an interior point with an activation
  keepEveryBlock(layout, block, grid, {&kept, &tight});
  EXPECT_TRUE(kept.keptAll());           // all 4 x 3 blocks
  EXPECT_EQ(kept.at(5, 7), 5007.0);      // activated
  EXPECT_EQ(kept.at(16, 9), 16009.0);    // a leaf line
  EXPECT_EQ(kept.at(40, 48), 40048.0);   // another
  EXPECT_EQ(kept.at(99, 50), 99050.0);   // the data's last column
  EXPECT_EQ(kept.at(120, 50), 99050.0);  // clamped to it
  EXPECT_EQ(kept.at(70, 69), 70069.0);   // the last row
  EXPECT_EQ(kept.misses(), 0u);
  // Not activated, on no line, and (for a 32-cell block) in no halo: a band along the borders.
  EXPECT_TRUE(std::isnan(kept.at(45, 43)));
  EXPECT_EQ(kept.misses(), 1u);
  EXPECT_LT(kept.keptSamples(), uint64_t(100) * 70);
  EXPECT_GT(kept.bytes(), 5000u);
  // Over its budget a store says it has not kept everything, and lets go of the blocks that did not
  // fit.
  EXPECT_FALSE(tight.keptAll());
  EXPECT_LE(tight.bytes(), 5000u);
}

// A staged build's pass-2 job restores the blocks its pass-1 job kept, and only those: a point on
// a block's left or top side is answered from the neighbour that holds it when the block itself is
// another job's; what does not fit a block is refused.
TEST(KeptHeights, RestoredBlocksAnswerTheirWholeClosedSquare) {
  const TreeLayout layout = makeTreeLayout(129, 129, 16).value();  // 4 x 4 blocks of 32
  const int32_t block = 32;
  KeptHeights kept(layout, block, uint64_t{1} << 30);
  ActivationGrid grid(layout.gridX(), layout.gridY());
  grid.set(37, 41, 2);
  keepEveryBlock(layout, block, grid, {&kept});
  // One job's block, (32, 32): its right and bottom sides belong to blocks it does not hold.
  KeptHeights job(layout, block, uint64_t{1} << 30);
  const GridPoint origin{32, 32};
  const auto bits = kept.blockBits(origin);
  const auto values = kept.blockValues(origin);
  ASSERT_FALSE(values.empty());
  EXPECT_FALSE(
      job.restoreBlock(origin, {bits.begin(), bits.end() - 1}, {values.begin(), values.end()}));
  EXPECT_FALSE(
      job.restoreBlock(origin, {bits.begin(), bits.end()}, {values.begin(), values.end() - 1}));
  EXPECT_FALSE(
      job.restoreBlock({16, 32}, {bits.begin(), bits.end()}, {values.begin(), values.end()}));
  ASSERT_TRUE(job.restoreBlock(origin, {bits.begin(), bits.end()}, {values.begin(), values.end()}));
  EXPECT_EQ(job.at(37, 41), 37041.0);  // activated
  EXPECT_EQ(job.at(32, 50), 32050.0);  // its own left side
  EXPECT_EQ(job.at(64, 50), 64050.0);  // its right side: block (64, 32) is not held
  EXPECT_EQ(job.at(50, 64), 50064.0);  // its bottom side
  EXPECT_EQ(job.at(64, 64), 64064.0);  // its far corner
  EXPECT_EQ(job.misses(), 0u);
  EXPECT_TRUE(std::isnan(job.at(65, 50)));  // inside a block it does not hold
  EXPECT_TRUE(std::isnan(job.at(20, 50)));
  EXPECT_EQ(job.misses(), 2u);
  EXPECT_FALSE(job.keptAll());
}

}  // namespace
}  // namespace terralod
