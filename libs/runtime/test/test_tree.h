#pragma once
// Test fixtures for the runtime: a complete in-memory chunk tree (no file involved) and a
// camera helper.

#include <vector>

#include "terralod/runtime/chunk_tree.h"
#include "terralod/runtime/view.h"

namespace terralod {

// A complete in-memory quadtree over a square of `cells` cells at 1 m, heights 0..100 m,
// δ(L) = 16 / 2^L metres; no file involved.
struct FullTree {
  TilesetHeader header;
  std::vector<NodeRecord> nodes;

  explicit FullTree(int levels, uint32_t cells = 1024) {
    header.levelCount = uint32_t(levels);
    header.rootCells = cells;
    header.leafCells = cells >> (levels - 1);
    header.rootsX = header.rootsY = 1;
    header.sourceColumns = header.sourceRows = cells + 1;
    for (int l = 0; l < levels; ++l) header.levelError[size_t(l)] = 16.0 / double(1 << l);
    header.extentMax = {double(cells), double(cells), 100.0};
    // Breadth-first, children in SW, SE, NW, NE order.
    nodes.push_back(NodeRecord{});
    for (size_t i = 0; i < nodes.size(); ++i) {
      NodeRecord& n = nodes[i];
      n.minZ = 0.0f;
      n.maxZ = 100.0f;
      n.triangleCount = 100;
      n.maxSkirtDepth = 5.0f;
      if (int(n.level) + 1 >= levels) continue;
      n.childMask = 0xF;
      n.firstChild = uint32_t(nodes.size());
      const NodeRecord parent = n;  // push_back may move it
      for (uint32_t k = 0; k < 4; ++k) {
        NodeRecord c;
        c.level = uint8_t(parent.level + 1);
        c.x = parent.x * 2 + (k & 1);
        c.y = parent.y * 2 + (k >> 1);
        c.parent = uint32_t(i);
        nodes.push_back(c);
      }
    }
  }
  ChunkTree tree() const { return ChunkTree(header, nodes); }
};

inline View viewFrom(glm::dvec3 eye, glm::dvec3 target, int width = 1000) {
  Camera c;
  c.eye = eye;
  c.target = target;
  c.width = width;
  c.height = width * 3 / 4;
  c.hfovDegrees = 90.0;  // K = width / 2
  return makeView(c).value();
}

}  // namespace terralod
