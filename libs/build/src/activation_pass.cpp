#include "terralod/build/activation_pass.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <vector>

#include "block_pass.h"
#include "terralod/core/bintree.h"
#include "terralod/core/parallel.h"
#include "triangle_scan.h"

namespace terralod {
namespace {

// Triangles larger than a block: bounds from their children only, on the lattice of half-block
// points (block corners, border midpoints and centres).
class CoarsePass {
 public:
  CoarsePass(const TreeLayout& layout, const ErrorBudget& budget, const HeightSampler& points,
             ActivationGrid& grid, int32_t block)
      : mLayout(layout),
        mBudget(budget),
        mPoints(points),
        mGrid(grid),
        mHalf(block / 2),
        mLatticeX(layout.gridX() / mHalf + 1),
        mLatticeY(layout.gridY() / mHalf + 1),
        mErrors(size_t(mLatticeX) * mLatticeY) {}

  void setBlockSquare(GridPoint center, const std::array<TriangleErrorBounds, 2>& e) {
    mErrors[latticeIndex(center)] = e;
  }

  void run(int32_t block) {
    for (int32_t h = block; h <= mLayout.rootCells / 2; h *= 2) {
      for (int32_t y = 0; y <= mLayout.gridY(); y += 2 * h)
        for (int32_t x = h; x <= mLayout.gridX(); x += 2 * h) vertex({x, y}, h, 0);
      for (int32_t y = h; y <= mLayout.gridY(); y += 2 * h)
        for (int32_t x = 0; x <= mLayout.gridX(); x += 2 * h) vertex({x, y}, h, 1);
      for (int32_t y = h; y <= mLayout.gridY(); y += 2 * h)
        for (int32_t x = h; x <= mLayout.gridX(); x += 2 * h) vertex({x, y}, h, 2);
    }
  }

 private:
  size_t latticeIndex(GridPoint p) const { return size_t(p.y / mHalf) * mLatticeX + p.x / mHalf; }

  // kind: 0 horizontal edge, 1 vertical edge, 2 square centre.
  void vertex(GridPoint v, int32_t h, int kind) {
    const VertexClass cls = kind == 2 ? VertexClass{VertexKind::kSquareCenter, h, false}
                                      : VertexClass{VertexKind::kEdgeMidpoint, h, kind == 0};
    const auto tris = diamondTriangles(v, cls);
    const bool rising = kind == 2 && squareHasRisingDiagonal(v.x - h, v.y - h, 2 * h);
    auto& slots = mErrors[latticeIndex(v)];
    uint8_t activation = 0;
    for (int s = 0; s < 2; ++s) {
      if (!insideGrid(tris[s], mLayout.gridX(), mLayout.gridY())) continue;
      const auto kids = childSlots(cls, rising, s);
      TriangleErrorBounds e;
      float childAbove = 0, childBelow = 0;
      for (const ChildSlot& c : kids) {
        const GridPoint k{v.x + c.dx, v.y + c.dy};
        activation = std::max(activation, mGrid.get(k.x, k.y));
        const auto& ke = mErrors[latticeIndex(k)][c.slot];
        childAbove = std::max(childAbove, ke.above);
        childBelow = std::max(childBelow, ke.below);
      }
      const BinTriangle& t = tris[s];
      if (std::min({t.a.x, t.b.x, t.apex.x}) <= mLayout.cellsX &&
          std::min({t.a.y, t.b.y, t.apex.y}) <= mLayout.cellsY) {
        const double d =
            mPoints.at(v.x, v.y) - 0.5 * (mPoints.at(t.a.x, t.a.y) + mPoints.at(t.b.x, t.b.y));
        e = {roundUp(childAbove + std::max(0.0, d)), roundUp(childBelow + std::max(0.0, -d))};
      }
      slots[s] = e;
      activation = std::max(activation, mBudget.activation(std::max(e.above, e.below)));
    }
    mGrid.set(v.x, v.y, std::max(activation, mGrid.get(v.x, v.y)));
  }

  const TreeLayout& mLayout;
  const ErrorBudget& mBudget;
  const HeightSampler& mPoints;
  ActivationGrid& mGrid;
  int32_t mHalf, mLatticeX, mLatticeY;
  std::vector<std::array<TriangleErrorBounds, 2>> mErrors;
};

// Raises every vertex to at least the activation of the vertices that depend on it, starting
// from the borders of `block`-sized blocks (the only places where pass 1 could have left the
// invariant broken).
void propagateBorders(const TreeLayout& layout, ActivationGrid& grid, int32_t block) {
  const int32_t side = layout.gridSide();
  std::vector<GridPoint> stack;
  for (int32_t y = 0; y <= layout.gridY(); ++y) {
    if (y % block == 0) {
      for (int32_t x = 0; x <= layout.gridX(); ++x) stack.push_back({x, y});
    } else {
      for (int32_t x = 0; x <= layout.gridX(); x += block) stack.push_back({x, y});
    }
  }
  while (!stack.empty()) {
    const GridPoint v = stack.back();
    stack.pop_back();
    const uint8_t a = grid.get(v.x, v.y);
    if (a == 0) continue;
    const VertexClass cls = classifyVertex(v.x, v.y, side);
    if (cls.kind == VertexKind::kCorner || cls.half >= layout.rootCells) continue;
    for (const GridPoint p : dependencyParents(v, cls)) {
      if (!insideGrid(p, layout.gridX(), layout.gridY())) continue;
      if (grid.get(p.x, p.y) < a) {
        grid.set(p.x, p.y, a);
        stack.push_back(p);
      }
    }
  }
}

}  // namespace

Result<ActivationGrid> computeActivations(const TreeLayout& layout, const ErrorBudget& budget,
                                          HeightWindows& windows, const HeightSampler& points,
                                          const ActivationOptions& options, Progress& progress,
                                          ActivationStats* stats) {
  const int32_t block = std::clamp(options.blockCells, layout.leafCells, layout.rootCells);
  ActivationGrid grid(layout.gridX(), layout.gridY());
  const int32_t blocksX = layout.gridX() / block, blocksY = layout.gridY() / block;
  const unsigned threads = std::max(1u, options.threads);

  std::vector<BlockResult> results(size_t(blocksX) * blocksY);
  std::vector<BlockScratch> scratch(threads);
  std::vector<ActivationStats> workerStats(threads);
  std::vector<Status> workerStatus(threads);
  std::atomic<bool> failed{false};

  progress.begin("errors", results.size());
  parallelFor(results.size(), threads, [&](size_t i, unsigned worker) {
    progress.advance();
    if (failed) return;
    const int32_t bx = int32_t(i % blocksX) * block, by = int32_t(i / blocksX) * block;
    if (bx >= layout.cellsX || by >= layout.cellsY) return;  // wholly padding: all zero
    BlockScratch& s = scratch[worker];
    s.reset(block);
    if (Status st = windows.read(bx, by, block + 1, block + 1, s.heights.data(), worker); !st) {
      workerStatus[worker] = st;
      failed = true;
      return;
    }
    BlockGeometry geometry;
    geometry.side = block;
    geometry.origin = {bx, by};
    geometry.realX = std::min(block, layout.cellsX - bx);
    geometry.realY = std::min(block, layout.cellsY - by);
    computeBlock(geometry, budget, s, grid, results[i], workerStats[worker]);
  });
  progress.end();
  for (const Status& st : workerStatus)
    if (!st) return st.error();

  // Borders: the maximum of both sides' one-sided activations.
  for (const BlockResult& r : results)
    for (const auto& [p, a] : r.border)
      if (grid.get(p.x, p.y) < a) grid.set(p.x, p.y, a);

  CoarsePass coarse(layout, budget, points, grid, block);
  for (size_t i = 0; i < results.size(); ++i) {
    if (!results[i].computed) continue;
    const GridPoint c{int32_t(i % blocksX) * block + block / 2,
                      int32_t(i / blocksX) * block + block / 2};
    coarse.setBlockSquare(c, results[i].squareErrors);
  }
  coarse.run(block);
  propagateBorders(layout, grid, block);

  if (stats) {
    for (const ActivationStats& w : workerStats) {
      stats->trianglesScanned += w.trianglesScanned;
      stats->trianglesBounded += w.trianglesBounded;
    }
  }
  return grid;
}

}  // namespace terralod
