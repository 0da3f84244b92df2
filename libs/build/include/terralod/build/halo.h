#pragma once
// The halo of a block: the points of its closed square that finishing pass 1's borders can
// change. Pass 1 computes every block on its own, so the only places its activations can still
// break the saturation invariant are the block borders; finishing them (border_reduce.h) raises
// border points and then, following dependencies (dependencyParents), coarser points. From a
// point inside a block those lead only to points of the same closed square, so the points the
// reduce can reach are, per block, its border points and everything their dependencies reach
// inside the square: a band a few points wide at each level, O(side) points rather than side².
//
// A cluster build's reduce holds only the halos (HaloStore), never the whole activation grid.

#include <cstddef>
#include <cstdint>
#include <vector>

#include "terralod/build/tree_layout.h"
#include "terralod/core/bintree.h"

namespace terralod {

/// A block's halo: local point indices ly * (side + 1) + lx, ascending.
struct HaloPattern {
  int32_t side = 0;
  std::vector<uint32_t> points;
  bool operator==(const HaloPattern&) const = default;
};

/// The halo of the block of side `block` whose south-west corner is `origin`.
HaloPattern haloOf(const TreeLayout& layout, GridPoint origin, int32_t block);

/// Every block's halo (the first block's): a block's interior and border points fall in the
/// same vertex classes wherever it is (origins are multiples of its power-of-two side), and the
/// block centre's dependency parents are its corners, border points anyway, so one pattern
/// serves all of them (`KeptHeights.OneHaloServesEveryBlock` checks it against haloOf for every
/// block of five layouts).
HaloPattern blockHalo(const TreeLayout& layout, int32_t block);

/// The activations of every block's halo. Points on a border shared by several blocks have one
/// copy per block; set() writes all of them. Every block has the same pattern (blockHalo).
class HaloStore {
 public:
  HaloStore(const TreeLayout& layout, int32_t block);

  int32_t blocksX() const { return mBlocksX; }
  int32_t blocksY() const { return mBlocksY; }
  size_t blockCount() const { return mValues.size(); }
  GridPoint origin(size_t block) const {
    return {int32_t(block % size_t(mBlocksX)) * mBlock, int32_t(block / size_t(mBlocksX)) * mBlock};
  }
  const HaloPattern& pattern(size_t) const { return mPattern; }
  /// Values in the order of pattern(block).points.
  std::vector<uint8_t>& values(size_t block) { return mValues[block]; }
  const std::vector<uint8_t>& values(size_t block) const { return mValues[block]; }

  /// Makes every copy of a shared border point the largest of them (pass 1 computed each side
  /// of a border from its own block only).
  void mergeBorders();

  uint8_t get(int32_t x, int32_t y) const;
  void set(int32_t x, int32_t y, uint8_t value);
  /// Points read or written that are in no halo: a broken assumption, reported as a bug.
  uint64_t misses() const { return mMisses; }

 private:
  ptrdiff_t slot(size_t block, int32_t x, int32_t y) const;
  template <typename F>
  void forEachCopy(int32_t x, int32_t y, F&& f);

  int32_t mBlock, mBlocksX, mBlocksY;
  HaloPattern mPattern;
  std::vector<std::vector<uint8_t>> mValues;
  mutable uint64_t mMisses = 0;
};

}  // namespace terralod
