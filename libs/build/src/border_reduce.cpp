#include "border_reduce.h"

#include <algorithm>

#include "terralod/build/activation_grid.h"
#include "terralod/build/halo.h"
#include "terralod/core/bintree.h"

namespace terralod {
namespace {

// Triangles larger than a block: bounds from their children only, on the lattice of half-block
// points (block corners, border midpoints and centres).
template <class Store>
class CoarsePass {
 public:
  CoarsePass(const TreeLayout& layout, const ErrorBudget& budget, const HeightSampler& points,
             Store& grid, int32_t block)
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
  Store& mGrid;
  int32_t mHalf, mLatticeX, mLatticeY;
  std::vector<std::array<TriangleErrorBounds, 2>> mErrors;
};

// Raises every vertex to at least the activation of the vertices that depend on it, starting
// from the borders of `block`-sized blocks (the only places where pass 1 could have left the
// invariant broken).
template <class Store>
void propagateBorders(const TreeLayout& layout, Store& grid, int32_t block) {
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

template <class Store>
void finishBorders(const TreeLayout& layout, const ErrorBudget& budget, const HeightSampler& points,
                   Store& store, int32_t block, const std::vector<BlockSquare>& squares) {
  const int32_t blocksX = layout.gridX() / block;
  CoarsePass<Store> coarse(layout, budget, points, store, block);
  for (size_t i = 0; i < squares.size(); ++i) {
    if (!squares[i].computed) continue;
    const GridPoint c{int32_t(i % blocksX) * block + block / 2,
                      int32_t(i / blocksX) * block + block / 2};
    coarse.setBlockSquare(c, squares[i].errors);
  }
  coarse.run(block);
  propagateBorders(layout, store, block);
}

template void finishBorders<ActivationGrid>(const TreeLayout&, const ErrorBudget&,
                                            const HeightSampler&, ActivationGrid&, int32_t,
                                            const std::vector<BlockSquare>&);
template void finishBorders<HaloStore>(const TreeLayout&, const ErrorBudget&, const HeightSampler&,
                                       HaloStore&, int32_t, const std::vector<BlockSquare>&);

}  // namespace terralod
