#pragma once
// The heights pass 2 of an untextured RTIN build reads, kept by pass 1 block by block as it
// decodes them, so that a streamed raster is decoded once without a copy of every sample, for
// any raster whose kept share fits the memory budget: an 8193^2 build keeps 2-6 % of its
// 268 MB of heights and peaks at 190-200 MB instead of 430. Per block, the points of its
// closed square that:
// - are a vertex at some level (activation above zero when pass 1 computed the block);
// - finishing the borders can still raise (the block's halo, halo.h);
// - lie on a leaf-chunk line (chunk sides: skirts measure the data along them) or on the data's
//   last row or column (where clipped triangles and clamped reads land).
// Those are every height the chunk mesher reads (chunk_mesher.cpp): vertices, the corners of
// the parent level's triangles, and the samples along chunk sides. A read of any other point
// counts as a miss and returns NaN; the build reports misses as an internal error.

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "terralod/build/activation_grid.h"
#include "terralod/build/halo.h"
#include "terralod/build/height_source.h"
#include "terralod/build/tree_layout.h"
#include "terralod/core/bintree.h"

namespace terralod {

class KeptHeights final : public HeightSampler {
 public:
  /// Blocks of side `block` (a power of two, a multiple of the leaf cells) as pass 1
  /// computes them, in at most `budgetBytes`: past that it keeps nothing more and keptAll() is
  /// false (its owner drops it, and pass 2 reads the raster again).
  KeptHeights(const TreeLayout& layout, int32_t block, uint64_t budgetBytes);

  /// Keeps the block at `origin`: `window` is its closed square's (block + 1)^2 samples in grid
  /// order, `grid` the activations pass 1 has just computed inside it. Replaces what an earlier
  /// pass kept there. Thread-safe for distinct blocks; reads no point another block writes.
  void keepBlock(GridPoint origin, const float* window, const ActivationGrid& grid);

  /// One block's kept points as keepBlock made them (empty if it kept nothing there): a bit
  /// per point of its closed square in grid order, and the kept heights in that order. What a
  /// staged build's pass-1 job hands its pass-2 job.
  std::span<const uint64_t> blockBits(GridPoint origin) const;
  std::span<const float> blockValues(GridPoint origin) const;
  /// Lets go of what the store keeps for the block at `origin` (once handed on).
  void dropBlock(GridPoint origin);
  /// Puts back what blockBits and blockValues gave for the block at `origin`; false (nothing
  /// kept) if they do not fit a block of this store. Thread-safe as keepBlock.
  bool restoreBlock(GridPoint origin, std::vector<uint64_t> bits, std::vector<float> values);

  /// Height at a grid point, clamped to the data; NaN (and a miss) where nothing was kept. A
  /// point on a block's left or top side is in its neighbour's closed square too: a store
  /// holding only some blocks (a staged job's) answers from whichever of them it holds.
  double at(int32_t x, int32_t y) const override;
  uint64_t misses() const { return mMisses.load(); }
  /// Samples kept over every block (points on shared block borders once per block).
  uint64_t keptSamples() const;
  /// Whether every block pass 1 computes (those with a corner inside the data) is kept and
  /// the budget held: what pass 2 needs to read only this store.
  bool keptAll() const;
  /// Bytes held (heights and their index).
  uint64_t bytes() const { return mBytes.load(); }
  /// The halo keepBlock uses for every block (what haloOf gives for each; tests check it).
  const HaloPattern& halo() const { return mHalo; }

 private:
  struct Block {
    std::vector<uint64_t> bits;   // which points of the closed square are kept
    std::vector<uint32_t> ranks;  // kept points before each word of bits
    std::vector<float> values;    // their heights, in point order
  };
  Block& blockAt(GridPoint origin);
  const Block& blockAt(GridPoint origin) const;
  // Counts a block (its bits, ranks and values filled in) in the bytes held; lets it go when
  // the budget is exceeded.
  void account(Block& b);
  // The height of point (lx, ly) of block (bx, by) into `out`; false where not kept.
  [[gnu::always_inline]] bool lookup(int32_t bx, int32_t by, int32_t lx, int32_t ly,
                                     double& out) const;
  // at() where block (bx, by) has not kept point (lx, ly): a neighbour's, or a miss.
  [[gnu::noinline, gnu::cold]] double notInBlock(int32_t bx, int32_t by, int32_t lx,
                                                 int32_t ly) const;
  const TreeLayout& mLayout;
  int32_t mBlock, mBlockLog2;
  int32_t mBlocksX, mBlocksY;
  HaloPattern mHalo;  // every block's (blockHalo)
  std::vector<Block> mBlocks;
  uint64_t mBudget;
  std::atomic<uint64_t> mBytes{0};
  std::atomic<bool> mOverBudget{false};
  mutable std::atomic<uint64_t> mMisses{0};
};

}  // namespace terralod
