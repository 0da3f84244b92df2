#include "terralod/build/halo.h"

#include <algorithm>

namespace terralod {

HaloPattern haloOf(const TreeLayout& layout, GridPoint origin, int32_t block) {
  const int32_t stride = block + 1;
  std::vector<uint8_t> seen(size_t(stride) * stride, 0);
  std::vector<GridPoint> stack;
  auto visit = [&](GridPoint p) {
    const int32_t lx = p.x - origin.x, ly = p.y - origin.y;
    if (lx < 0 || ly < 0 || lx > block || ly > block) return;
    uint8_t& s = seen[size_t(ly) * stride + lx];
    if (s) return;
    s = 1;
    stack.push_back(p);
  };
  for (int32_t i = 0; i <= block; ++i) {
    visit({origin.x + i, origin.y});
    visit({origin.x + i, origin.y + block});
    visit({origin.x, origin.y + i});
    visit({origin.x + block, origin.y + i});
  }
  // The same walk as the reduce's propagation (border_reduce.cpp), without the values.
  const int32_t side = layout.gridSide();
  while (!stack.empty()) {
    const GridPoint v = stack.back();
    stack.pop_back();
    const VertexClass cls = classifyVertex(v.x, v.y, side);
    if (cls.kind == VertexKind::kCorner || cls.half >= layout.rootCells) continue;
    for (const GridPoint p : dependencyParents(v, cls))
      if (insideGrid(p, layout.gridX(), layout.gridY())) visit(p);
  }
  HaloPattern halo;
  halo.side = block;
  for (uint32_t i = 0; i < seen.size(); ++i)
    if (seen[i]) halo.points.push_back(i);
  return halo;
}

HaloPattern blockHalo(const TreeLayout& layout, int32_t block) {
  return haloOf(layout, {0, 0}, block);
}

HaloStore::HaloStore(const TreeLayout& layout, int32_t block)
    : mBlock(block),
      mBlocksX(layout.gridX() / block),
      mBlocksY(layout.gridY() / block),
      mPattern(blockHalo(layout, block)),
      mValues(size_t(mBlocksX) * size_t(mBlocksY), std::vector<uint8_t>(mPattern.points.size())) {}

ptrdiff_t HaloStore::slot(size_t block, int32_t x, int32_t y) const {
  const GridPoint o = origin(block);
  const uint32_t local = uint32_t(y - o.y) * uint32_t(mBlock + 1) + uint32_t(x - o.x);
  const auto& points = mPattern.points;
  const auto it = std::lower_bound(points.begin(), points.end(), local);
  if (it == points.end() || *it != local) return -1;
  return it - points.begin();
}

uint8_t HaloStore::get(int32_t x, int32_t y) const {
  const int32_t bx = std::min(x / mBlock, mBlocksX - 1), by = std::min(y / mBlock, mBlocksY - 1);
  const size_t block = size_t(by) * mBlocksX + bx;
  const ptrdiff_t s = slot(block, x, y);
  if (s < 0) {
    ++mMisses;
    return 0;
  }
  return mValues[block][size_t(s)];
}

template <typename F>
void HaloStore::forEachCopy(int32_t x, int32_t y, F&& f) {
  const int32_t bx1 = std::min(x / mBlock, mBlocksX - 1), by1 = std::min(y / mBlock, mBlocksY - 1);
  const int32_t bx0 = x % mBlock == 0 && x > 0 ? x / mBlock - 1 : bx1;
  const int32_t by0 = y % mBlock == 0 && y > 0 ? y / mBlock - 1 : by1;
  for (int32_t by = by0; by <= by1; ++by)
    for (int32_t bx = bx0; bx <= bx1; ++bx) {
      const size_t block = size_t(by) * mBlocksX + bx;
      const ptrdiff_t s = slot(block, x, y);
      if (s < 0) {
        ++mMisses;
        continue;
      }
      f(mValues[block][size_t(s)]);
    }
}

void HaloStore::set(int32_t x, int32_t y, uint8_t value) {
  forEachCopy(x, y, [&](uint8_t& copy) { copy = value; });
}

void HaloStore::mergeBorders() {
  const uint32_t stride = uint32_t(mBlock) + 1;
  for (size_t b = 0; b < mValues.size(); ++b) {
    const GridPoint o = origin(b);
    const auto& points = mPattern.points;
    for (size_t i = 0; i < points.size(); ++i) {
      const int32_t lx = int32_t(points[i] % stride), ly = int32_t(points[i] / stride);
      if (lx != 0 && ly != 0 && lx != mBlock && ly != mBlock) continue;
      // This copy is at least its block's own value; every copy becomes at least it.
      const uint8_t value = mValues[b][i];
      forEachCopy(o.x + lx, o.y + ly, [&](uint8_t& copy) { copy = std::max(copy, value); });
    }
  }
}

}  // namespace terralod
