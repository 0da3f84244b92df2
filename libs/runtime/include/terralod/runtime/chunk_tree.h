#pragma once
// The chunk quadtree as the runtime sees it: per node its world bounding box, level, error and
// children, laid out for a fast traversal. Built once from a tileset's header and node table;
// independent of how a chunk's geometry is stored (the node's MeshKind is carried, not used).

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "terralod/format/tileset_format.h"

namespace terralod {

/// An axis-aligned box in world metres.
struct Box {
  std::array<double, 3> min{}, max{};
};

struct ChunkNode {
  /// Footprint clipped to the data x [minZ, maxZ] of the drawn surface, grown to hold its
  /// children's boxes (nested: a child's box is never nearer the eye than its parent's).
  Box box;
  double skirtBottom = 0;  ///< lowest point of its skirts (for culling)
  uint32_t firstChild = kNoNode;
  uint32_t parent = kNoNode;
  uint8_t childCount = 0;  ///< children are firstChild .. firstChild + childCount - 1
  uint8_t level = 0;
  MeshKind meshKind = MeshKind::kStaticRtin;
  bool inheritsTexture = false;  ///< draws an ancestor's texture (kNodeInheritsTexture)
  uint32_t triangleCount = 0;    ///< surface triangles
  uint32_t skirtTriangleCount = 0;
};

/// Safe to share between threads: only an edit changes it (updateNode, setLevelError), on
/// the thread that selects, and loader threads read only the structure and mesh kinds.
class ChunkTree {
 public:
  /// `header` and `nodes` must have passed the format's validation (TilesetReader does that).
  ChunkTree(const TilesetHeader& header, std::span<const NodeRecord> nodes);

  /// An edit's new record for node i: its box's heights, skirt bottom and triangle counts.
  void updateNode(uint32_t i, const NodeRecord& record);
  /// An edit's new level error (a VIPM tileset's roots).
  void setLevelError(uint32_t level, double error) { mLevelError[level] = error; }

  const std::vector<ChunkNode>& nodes() const { return mNodes; }
  const ChunkNode& node(uint32_t i) const { return mNodes[i]; }
  /// The roots, in node order (they are nodes 0 .. rootCount-1).
  uint32_t rootCount() const { return mRootCount; }
  /// Geometric error δ of a level in metres (root level 0 first).
  double levelError(int level) const { return mLevelError[size_t(level)]; }
  int levelCount() const { return int(mLevelError.size()); }
  const Box& extent() const { return mExtent; }
  /// Metres per grid cell along x (east) and y (north).
  const std::array<double, 2>& spacing() const { return mSpacing; }
  /// Side of a chunk's square at a level, in grid cells (its texture spans this square).
  int32_t chunkCells(int level) const { return mRootCells >> level; }

 private:
  std::vector<ChunkNode> mNodes;
  std::vector<double> mLevelError;
  uint32_t mRootCount = 0;
  int32_t mRootCells = 0;
  Box mExtent;
  std::array<double, 2> mSpacing{1.0, 1.0};
};

}  // namespace terralod
