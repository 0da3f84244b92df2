#include "terralod/build/activation_pass.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <vector>

#include "terralod/core/bintree.h"
#include "terralod/core/parallel.h"
#include "triangle_scan.h"

namespace terralod {
namespace {

struct BlockScratch {
  std::array<std::vector<float>, 2> above, below;
  std::vector<uint8_t> act;
  std::vector<float> heights;
  void reset(int32_t side) {
    const size_t n = size_t(side + 1) * (side + 1);
    for (int s = 0; s < 2; ++s) {
      above[s].assign(n, 0.0f);
      below[s].assign(n, 0.0f);
    }
    act.assign(n, 0);
    heights.resize(n);
  }
};

struct BlockResult {
  std::vector<std::pair<GridPoint, uint8_t>> border;  // one-sided activations, global coords
  std::array<TriangleErrorBounds, 2> squareErrors;
  bool computed = false;
};

// Pass 1 over one block: heights in scratch.heights, writes interior activations to the grid.
class BlockPass {
 public:
  BlockPass(BlockScratch& s, const ErrorBudget& budget, ActivationGrid& grid, int32_t side,
            GridPoint origin, int32_t realX, int32_t realY, ActivationStats& stats)
      : mS(s),
        mBudget(budget),
        mGrid(grid),
        mSide(side),
        mStride(side + 1),
        mOrigin(origin),
        mRealX(realX),
        mRealY(realY),
        mStats(stats) {}

  void run(BlockResult& out) {
    for (int32_t h = 1; h <= mSide / 2; h *= 2) {
      for (int32_t y = 0; y <= mSide; y += 2 * h)
        for (int32_t x = h; x <= mSide; x += 2 * h) edge(x, y, h, true, out);
      for (int32_t y = h; y <= mSide; y += 2 * h)
        for (int32_t x = 0; x <= mSide; x += 2 * h) edge(x, y, h, false, out);
      for (int32_t y = h; y <= mSide; y += 2 * h)
        for (int32_t x = h; x <= mSide; x += 2 * h) center(x, y, h);
    }
    const size_t c = index(mSide / 2, mSide / 2);
    for (int s = 0; s < 2; ++s) out.squareErrors[s] = {mS.above[s][c], mS.below[s][c]};
    out.computed = true;
  }

 private:
  size_t index(int32_t x, int32_t y) const { return size_t(y) * mStride + x; }
  float height(GridPoint p) const { return mS.heights[index(p.x, p.y)]; }
  bool real(GridPoint p) const { return p.x <= mRealX && p.y <= mRealY; }
  bool touchesData(const BinTriangle& t) const {
    return std::min({t.a.x, t.b.x, t.apex.x}) <= mRealX &&
           std::min({t.a.y, t.b.y, t.apex.y}) <= mRealY;
  }

  // Error bounds of slot triangle t of vertex v; returns its activation.
  uint8_t slot(GridPoint v, int slotIndex, const BinTriangle& t, const ChildSlot* children,
               uint8_t childActivation) {
    TriangleErrorBounds e;
    if (touchesData(t)) {
      const double d = double(height(v)) - 0.5 * (double(height(t.a)) + double(height(t.b)));
      if (!children) {
        // Smallest diamonds: the midpoint is the only sample off the triangle's corners.
        if (real(v)) e = {roundUp(std::max(0.0, d)), roundUp(std::max(0.0, -d))};
      } else {
        float childAbove = 0, childBelow = 0;
        for (int c = 0; c < 2; ++c) {
          const size_t i = index(v.x + children[c].dx, v.y + children[c].dy);
          childAbove = std::max(childAbove, mS.above[children[c].slot][i]);
          childBelow = std::max(childBelow, mS.below[children[c].slot][i]);
        }
        e = {roundUp(childAbove + std::max(0.0, d)), roundUp(childBelow + std::max(0.0, -d))};
        if (mBudget.activation(std::max(e.above, e.below)) > childActivation) {
          e = scanTriangle(mS.heights.data(), mStride, t, mRealX, mRealY);
          ++mStats.trianglesScanned;
        } else {
          ++mStats.trianglesBounded;
        }
      }
    }
    const size_t i = index(v.x, v.y);
    mS.above[slotIndex][i] = e.above;
    mS.below[slotIndex][i] = e.below;
    return mBudget.activation(std::max(e.above, e.below));
  }

  void finish(GridPoint v, uint8_t activation, BlockResult& out) {
    mS.act[index(v.x, v.y)] = activation;
    const bool border = v.x == 0 || v.y == 0 || v.x == mSide || v.y == mSide;
    const GridPoint g{mOrigin.x + v.x, mOrigin.y + v.y};
    if (border) {
      if (activation) out.border.emplace_back(g, activation);
    } else {
      mGrid.set(g.x, g.y, activation);
    }
  }

  void edge(int32_t x, int32_t y, int32_t h, bool horizontal, BlockResult& out) {
    const GridPoint v{x, y};
    const VertexClass cls{VertexKind::kEdgeMidpoint, h, horizontal};
    const auto tris = diamondTriangles(v, cls);
    const bool inside[2] = {horizontal ? y + h <= mSide : x + h <= mSide,
                            horizontal ? y - h >= 0 : x - h >= 0};
    std::array<ChildSlot, 2> kids[2];
    uint8_t childActivation = 0;
    if (h >= 2) {
      for (int s = 0; s < 2; ++s) {
        if (!inside[s]) continue;
        kids[s] = childSlots(cls, false, s);
        for (const ChildSlot& c : kids[s])
          childActivation = std::max(childActivation, mS.act[index(x + c.dx, y + c.dy)]);
      }
    }
    uint8_t activation = childActivation;
    for (int s = 0; s < 2; ++s) {
      if (!inside[s]) continue;
      activation = std::max(
          activation, slot(v, s, tris[s], h >= 2 ? kids[s].data() : nullptr, childActivation));
    }
    finish(v, activation, out);
  }

  void center(int32_t x, int32_t y, int32_t h) {
    const GridPoint v{x, y};
    const bool rising = squareHasRisingDiagonal(mOrigin.x + x - h, mOrigin.y + y - h, 2 * h);
    // Local triangles with the diagonal chosen by global position.
    const GridPoint sw{x - h, y - h}, se{x + h, y - h}, nw{x - h, y + h}, ne{x + h, y + h};
    const std::array<BinTriangle, 2> tris =
        rising ? std::array<BinTriangle, 2>{BinTriangle{sw, ne, se}, BinTriangle{sw, ne, nw}}
               : std::array<BinTriangle, 2>{BinTriangle{nw, se, sw}, BinTriangle{nw, se, ne}};
    const VertexClass cls{VertexKind::kSquareCenter, h, false};
    std::array<ChildSlot, 2> kids[2] = {childSlots(cls, rising, 0), childSlots(cls, rising, 1)};
    uint8_t childActivation = 0;
    for (int s = 0; s < 2; ++s)
      for (const ChildSlot& c : kids[s])
        childActivation = std::max(childActivation, mS.act[index(x + c.dx, y + c.dy)]);
    uint8_t activation = childActivation;
    for (int s = 0; s < 2; ++s)
      activation = std::max(activation, slot(v, s, tris[s], kids[s].data(), childActivation));
    mS.act[index(x, y)] = activation;
    mGrid.set(mOrigin.x + x, mOrigin.y + y, activation);  // centres are never on a border
  }

  BlockScratch& mS;
  const ErrorBudget& mBudget;
  ActivationGrid& mGrid;
  int32_t mSide, mStride;
  GridPoint mOrigin;
  int32_t mRealX, mRealY;
  ActivationStats& mStats;
};

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
// from `seeds` (the only places where pass 1 could have left the invariant broken).
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
    BlockPass pass(s, budget, grid, block, {bx, by}, std::min(block, layout.cellsX - bx),
                   std::min(block, layout.cellsY - by), workerStats[worker]);
    pass.run(results[i]);
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
