#include "terralod/runtime/selection.h"

#include <algorithm>
#include <cassert>

namespace terralod {
namespace {

// The box that culling must keep: skirts hang below the surface's own box.
Box cullingBox(const ChunkNode& n) {
  Box b = n.box;
  b.min[2] = std::min(b.min[2], n.skirtBottom);
  return b;
}

bool canDraw(const SelectionOptions& o, uint32_t node) {
  return o.drawable.empty() || o.drawable[node] != 0;
}

double rhoOf(const ChunkTree& tree, const View& view, const ChunkNode& n) {
  return screenSpaceError(view, tree.levelError(n.level), distanceToBox(view.camera.eye, n.box));
}

float scheduleMorph(const ChunkTree& tree, const ChunkNode& n, double rho,
                    const SelectionOptions& o) {
  if (!o.morph || n.level == 0) return 0.0f;  // roots morph to themselves
  // δ_L / (δ_{L−1} − δ_L): exactly 1 where errors halve per level (selection.h).
  const double own = tree.levelError(n.level), parent = tree.levelError(n.level - 1);
  const double scale = parent > own ? own / (parent - own) : 1.0;
  return float(std::clamp((o.tau / rho - 1.0) * scale, 0.0, 1.0));
}

struct Traversal {
  const ChunkTree& tree;
  const View& view;
  const SelectionOptions& options;
  std::vector<SelectedChunk>& out;
  SelectionStats stats;

  void draw(uint32_t i, float morph) {
    const ChunkNode& n = tree.node(i);
    out.push_back({i, morph});
    ++stats.selected;
    stats.triangles += n.triangleCount;
    stats.skirtTriangles += n.skirtTriangleCount;
    stats.deepestLevel = std::max(stats.deepestLevel, int(n.level));
  }

  bool childrenDrawable(const ChunkNode& n) const {
    for (uint32_t c = n.firstChild; c < n.firstChild + n.childCount; ++c)
      if (!canDraw(options, c)) return false;
    return true;
  }

  // Recursion is bounded by the tree's depth (at most kMaxLevels).
  void visit(uint32_t i) {
    const ChunkNode& n = tree.node(i);
    ++stats.visited;
    if (!boxInFrustum(view, cullingBox(n))) {
      ++stats.culled;
      return;
    }
    const double rho = rhoOf(tree, view, n);
    const bool wantsSplit = rho > options.tau && n.childCount > 0;
    if (wantsSplit && childrenDrawable(n)) {
      for (uint32_t c = n.firstChild; c < n.firstChild + n.childCount; ++c) visit(c);
      return;
    }
    if (wantsSplit) ++stats.coarserThanWanted;
    draw(i, scheduleMorph(tree, n, rho, options));
  }
};

}  // namespace

SelectionStats selectChunks(const ChunkTree& tree, const View& view,
                            const SelectionOptions& options, std::vector<SelectedChunk>& out) {
  assert(options.tau > 0.0);
  assert(options.drawable.empty() || options.drawable.size() == tree.nodes().size());
  out.clear();
  Traversal t{tree, view, options, out, {}};
  for (uint32_t r = 0; r < tree.rootCount(); ++r) {
    if (canDraw(options, r)) {
      t.visit(r);
    } else if (boxInFrustum(view, cullingBox(tree.node(r)))) {
      ++t.stats.undrawableRoots;
    }
  }
  return t.stats;
}

float morphParameter(const ChunkTree& tree, const View& view, const SelectionOptions& options,
                     uint32_t node) {
  const ChunkNode& n = tree.node(node);
  return scheduleMorph(tree, n, rhoOf(tree, view, n), options);
}

}  // namespace terralod
