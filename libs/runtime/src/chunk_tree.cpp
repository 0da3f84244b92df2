#include "terralod/runtime/chunk_tree.h"

#include <algorithm>
#include <bit>

namespace terralod {
namespace {

// Grows `box`'s height range to hold `inner`'s.
void growZ(Box& box, const Box& inner) {
  box.min[2] = std::min(box.min[2], inner.min[2]);
  box.max[2] = std::max(box.max[2], inner.max[2]);
}

}  // namespace

ChunkTree::ChunkTree(const TilesetHeader& header, std::span<const NodeRecord> nodes) {
  const double cellsX = double(header.sourceColumns - 1), cellsY = double(header.sourceRows - 1);
  mNodes.resize(nodes.size());
  for (size_t i = 0; i < nodes.size(); ++i) {
    const NodeRecord& r = nodes[i];
    ChunkNode& n = mNodes[i];
    const double side = double(header.chunkCells(r.level));
    const double x0 = double(r.x) * side, y0 = double(r.y) * side;
    n.box.min = {x0 * header.spacingX, y0 * header.spacingY, double(r.minZ)};
    n.box.max = {std::min(x0 + side, cellsX) * header.spacingX,
                 std::min(y0 + side, cellsY) * header.spacingY, double(r.maxZ)};
    n.skirtBottom = double(r.minZ) - double(r.maxSkirtDepth);
    n.firstChild = r.firstChild;
    n.parent = r.parent;
    n.childCount = uint8_t(std::popcount(unsigned(r.childMask)));
    n.level = r.level;
    n.meshKind = r.meshKind;
    n.inheritsTexture = r.inheritsTexture();
    n.triangleCount = r.triangleCount;
    n.skirtTriangleCount = r.skirtTriangleCount;
    if (r.level == 0) ++mRootCount;
  }
  // Nested boxes: a node's box also holds its children's (breadth-first order puts every child
  // after its parent). A child's surface may rise above its parent's or dip below it; with a
  // box of its own it could then be nearer the eye than its parent's, and at the split its
  // screen error more than half the parent's: it would appear partly morphed, a pop. Nested,
  // a child is never nearer, so it starts fully morphed (selection.h).
  for (size_t i = nodes.size(); i-- > 0;)
    if (mNodes[i].parent != kNoNode) growZ(mNodes[mNodes[i].parent].box, mNodes[i].box);
  mLevelError.assign(header.levelError.begin(), header.levelError.begin() + header.levelCount);
  mExtent.min = header.extentMin;
  mExtent.max = header.extentMax;
  mSpacing = {header.spacingX, header.spacingY};
  mRootCells = int32_t(header.rootCells);
}

void ChunkTree::updateNode(uint32_t i, const NodeRecord& r) {
  ChunkNode& n = mNodes[i];
  n.box.min[2] = double(r.minZ);
  n.box.max[2] = double(r.maxZ);
  // Still nested: its children's boxes, and its ancestors' grow to hold it (they never shrink,
  // which keeps them conservative).
  for (uint32_t c = n.firstChild; n.childCount > 0 && c < n.firstChild + n.childCount; ++c)
    growZ(n.box, mNodes[c].box);
  for (uint32_t a = n.parent; a != kNoNode; a = mNodes[a].parent) growZ(mNodes[a].box, n.box);
  n.skirtBottom = double(r.minZ) - double(r.maxSkirtDepth);
  n.triangleCount = r.triangleCount;
  n.skirtTriangleCount = r.skirtTriangleCount;
  mExtent.min[2] = std::min(mExtent.min[2], double(r.minZ));
  mExtent.max[2] = std::max(mExtent.max[2], double(r.maxZ));
}

}  // namespace terralod
