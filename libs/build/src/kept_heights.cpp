#include "terralod/build/kept_heights.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>

namespace terralod {

KeptHeights::KeptHeights(const TreeLayout& layout, int32_t block, uint64_t budgetBytes)
    : mLayout(layout),
      mBlock(block),
      mBlockLog2(std::countr_zero(uint32_t(block))),
      mBlocksX(layout.gridX() / block),
      mBlocksY(layout.gridY() / block),
      mHalo(blockHalo(layout, block)),
      mBlocks(size_t(mBlocksX) * size_t(mBlocksY)),
      mBudget(budgetBytes) {}

namespace {

// Set bits of x, without a call: the build targets x86-64 without POPCNT, where std::popcount
// is a call into libgcc (2 % of a build through at()).
inline uint32_t bitCount(uint64_t x) {
  x -= (x >> 1) & 0x5555555555555555ull;
  x = (x & 0x3333333333333333ull) + ((x >> 2) & 0x3333333333333333ull);
  x = (x + (x >> 4)) & 0x0F0F0F0F0F0F0F0Full;
  return uint32_t((x * 0x0101010101010101ull) >> 56);
}

// Kept points before each word of `bits` into `ranks`; returns how many are kept.
size_t rankBits(const std::vector<uint64_t>& bits, std::vector<uint32_t>& ranks) {
  ranks.resize(bits.size());
  uint32_t kept = 0;
  for (size_t w = 0; w < bits.size(); ++w) {
    ranks[w] = kept;
    kept += bitCount(bits[w]);
  }
  return kept;
}

uint64_t bytesOf(const std::vector<uint64_t>& bits, const std::vector<uint32_t>& ranks,
                 const std::vector<float>& values) {
  return bits.capacity() * sizeof(uint64_t) + ranks.capacity() * sizeof(uint32_t) +
         values.capacity() * sizeof(float);
}

}  // namespace

KeptHeights::Block& KeptHeights::blockAt(GridPoint origin) {
  return mBlocks[size_t(origin.y / mBlock) * size_t(mBlocksX) + size_t(origin.x / mBlock)];
}

const KeptHeights::Block& KeptHeights::blockAt(GridPoint origin) const {
  return mBlocks[size_t(origin.y / mBlock) * size_t(mBlocksX) + size_t(origin.x / mBlock)];
}

void KeptHeights::keepBlock(GridPoint origin, const float* window, const ActivationGrid& grid) {
  if (mOverBudget) return;
  const int32_t side = mBlock, stride = side + 1;
  Block& b = blockAt(origin);
  mBytes -= bytesOf(b.bits, b.ranks, b.values);  // kept by an earlier pass: replaced
  const size_t points = size_t(stride) * size_t(stride);
  b.bits.assign((points + 63) / 64, 0);
  auto mark = [&](size_t i) { b.bits[i >> 6] |= uint64_t{1} << (i & 63); };
  for (const uint32_t i : mHalo.points) mark(i);
  const int32_t leaf = mLayout.leafCells;
  const int32_t lastX = std::min(side, mLayout.cellsX - origin.x);
  const int32_t lastY = std::min(side, mLayout.cellsY - origin.y);
  // Columns on leaf lines, and the data's last column.
  std::vector<int32_t> columns;
  for (int32_t lx = 0; lx <= lastX; lx += leaf) columns.push_back(lx);
  if (origin.x + lastX == mLayout.cellsX && lastX % leaf != 0) columns.push_back(lastX);
  const ActivationGrid::Nibbles& nibbles = grid.nibbles();
  const size_t rowBytes = (size_t(grid.cellsX()) + 2) / 2;
  for (int32_t ly = 0; ly <= lastY; ++ly) {
    const int32_t y = origin.y + ly;
    const size_t row = size_t(ly) * size_t(stride);
    if (y % leaf == 0 || y == mLayout.cellsY) {
      for (int32_t lx = 0; lx <= lastX; ++lx) mark(row + size_t(lx));
      continue;
    }
    for (const int32_t lx : columns) mark(row + size_t(lx));
    // Interior points with an activation: the grid's bytes of this block's row, eight at a
    // time (most are zero). Rows and columns on the block's border are leaf lines, so only
    // interior points are read, which this block's pass wrote and no other block's touches:
    // bytes (ox + 2k, ox + 2k + 1) for 2k + 1 < side (origins and sides are even).
    const uint8_t* bytes = nibbles.data() + size_t(y - grid.originY()) * rowBytes +
                           size_t(origin.x - grid.originX()) / 2;
    const size_t count = size_t(std::min(side, lastX + 1)) / 2;  // points lx < 2 * count
    for (size_t k = 0; k < count; k += 8) {
      uint64_t eight = 0;
      std::memcpy(&eight, bytes + k, std::min<size_t>(8, count - k));
      if (k == 0) eight &= ~uint64_t{0x0F};  // lx = 0: the border, kept already
      // One bit per nonzero nibble; nibble j of the eight bytes is point lx = 2k + j.
      uint64_t nonzero = (eight | eight >> 1 | eight >> 2 | eight >> 3) & 0x1111111111111111ull;
      for (; nonzero; nonzero &= nonzero - 1)
        mark(row + 2 * k + size_t(std::countr_zero(nonzero) / 4));
    }
  }
  b.values.clear();
  b.values.reserve(rankBits(b.bits, b.ranks));
  for (size_t w = 0; w < b.bits.size(); ++w)
    for (uint64_t bits = b.bits[w]; bits; bits &= bits - 1)
      b.values.push_back(window[w * 64 + size_t(std::countr_zero(bits))]);
  account(b);
}

void KeptHeights::account(Block& b) {
  // Over the budget, this block and every later one are let go; those kept before stay until
  // the owner drops the whole store (keptAll() says false).
  if ((mBytes += bytesOf(b.bits, b.ranks, b.values)) > mBudget) mOverBudget = true;
  if (mOverBudget) {
    mBytes -= bytesOf(b.bits, b.ranks, b.values);
    b = Block{};
  }
}

std::span<const uint64_t> KeptHeights::blockBits(GridPoint origin) const {
  return blockAt(origin).bits;
}

std::span<const float> KeptHeights::blockValues(GridPoint origin) const {
  return blockAt(origin).values;
}

void KeptHeights::dropBlock(GridPoint origin) {
  Block& b = blockAt(origin);
  mBytes -= bytesOf(b.bits, b.ranks, b.values);
  b = Block{};
}

bool KeptHeights::restoreBlock(GridPoint origin, std::vector<uint64_t> bits,
                               std::vector<float> values) {
  const size_t points = size_t(mBlock + 1) * size_t(mBlock + 1);
  if (origin.x < 0 || origin.y < 0 || origin.x % mBlock != 0 || origin.y % mBlock != 0 ||
      origin.x / mBlock >= mBlocksX || origin.y / mBlock >= mBlocksY ||
      bits.size() != (points + 63) / 64 || (points % 64 != 0 && bits.back() >> (points % 64) != 0))
    return false;
  std::vector<uint32_t> ranks;
  if (rankBits(bits, ranks) != values.size()) return false;
  if (mOverBudget) return true;
  Block& b = blockAt(origin);
  mBytes -= bytesOf(b.bits, b.ranks, b.values);
  b = {std::move(bits), std::move(ranks), std::move(values)};
  account(b);
  return true;
}

inline bool KeptHeights::lookup(int32_t bx, int32_t by, int32_t lx, int32_t ly, double& out) const {
  const Block& b = mBlocks[size_t(by) * size_t(mBlocksX) + size_t(bx)];
  const size_t i = size_t(ly) * size_t(mBlock + 1) + size_t(lx);
  const uint64_t bit = uint64_t{1} << (i & 63);
  const uint64_t word = (i >> 6) < b.bits.size() ? b.bits[i >> 6] : 0;
  if (!(word & bit)) return false;
  out = b.values[b.ranks[i >> 6] + bitCount(word & (bit - 1))];
  return true;
}

double KeptHeights::at(int32_t x, int32_t y) const {
  x = std::clamp(x, 0, mLayout.cellsX);
  y = std::clamp(y, 0, mLayout.cellsY);
  const int32_t bx = std::min(x >> mBlockLog2, mBlocksX - 1);
  const int32_t by = std::min(y >> mBlockLog2, mBlocksY - 1);
  const int32_t lx = x - (bx << mBlockLog2), ly = y - (by << mBlockLog2);
  double h = 0;
  if (lookup(bx, by, lx, ly, h)) [[likely]]
    return h;
  return notInBlock(bx, by, lx, ly);
}

double KeptHeights::notInBlock(int32_t bx, int32_t by, int32_t lx, int32_t ly) const {
  // On the block's left or top side: the neighbour's closed square has it as its right or
  // bottom side (every block keeps its whole border: block sides are leaf lines).
  double h = 0;
  if (mBlocks[size_t(by) * size_t(mBlocksX) + size_t(bx)].bits.empty()) {
    const bool left = lx == 0 && bx > 0, top = ly == 0 && by > 0;
    if ((left && lookup(bx - 1, by, mBlock, ly, h)) || (top && lookup(bx, by - 1, lx, mBlock, h)) ||
        (left && top && lookup(bx - 1, by - 1, mBlock, mBlock, h)))
      return h;
  }
  mMisses.fetch_add(1, std::memory_order_relaxed);
  return std::nan("");
}

uint64_t KeptHeights::keptSamples() const {
  uint64_t n = 0;
  for (const Block& b : mBlocks) n += b.values.size();
  return n;
}

bool KeptHeights::keptAll() const {
  if (mOverBudget) return false;
  // The blocks pass 1 computes: those with a corner inside the data.
  for (int32_t by = 0; by * mBlock < mLayout.cellsY; ++by)
    for (int32_t bx = 0; bx * mBlock < mLayout.cellsX; ++bx)
      if (mBlocks[size_t(by) * size_t(mBlocksX) + size_t(bx)].bits.empty()) return false;
  return true;
}

}  // namespace terralod
