#include "block_pass.h"

#include <algorithm>
#include <cmath>

namespace terralod {

void BlockScratch::reset(int32_t side) {
  const size_t n = size_t(side + 1) * (side + 1);
  slots.resize(n);
  activation.resize(n);
  heights.resize(n);
}

namespace {

// Which slot of a child vertex holds the child triangle, as an index offset from the parent.
struct Child {
  ptrdiff_t offset;
  int slot;
};

// One block, bottom-up: level E_h (edge midpoints of half length h), then S_2h (centres of
// squares of side 2h), for h = 1, 2, 4, ... Clipped blocks (data ends inside them) check which
// samples are real; the rest skip every such test.
template <bool kClipped>
class Pass {
 public:
  Pass(const BlockGeometry& g, const ErrorBudget& budget, BlockScratch& s, ActivationStats& stats)
      : mG(g),
        mBudget(budget),
        mS(s),
        mStats(stats),
        mStride(g.side + 1),
        mH(s.heights.data()),
        mE(s.slots.data()),
        mA(s.activation.data()) {}

  // Every slot and activation run() does not compute reads as zero: clipped blocks skip
  // samples past the data, so they start from zeros; whole blocks write every slot (those
  // outside the block as zeros) and leave only the corners.
  void run() {
    const int32_t s = mG.side;
    if (kClipped) {
      std::fill(mS.slots.begin(), mS.slots.end(), SlotErrors{{0, 0}, {0, 0}});
      std::fill(mS.activation.begin(), mS.activation.end(), uint8_t{0});
    } else {
      for (const size_t corner : {at(0, 0), at(s, 0), at(0, s), at(s, s)}) {
        mE[corner] = SlotErrors{{0, 0}, {0, 0}};
        mA[corner] = 0;
      }
    }
    smallestEdges();
    smallestCentres();
    for (int32_t h = 2; h <= mG.side / 2; h *= 2) {
      edges(h);
      centres(h);
    }
    // Counted here and added once, so that workers do not write to the cache line their
    // stats share (they sit side by side) on every triangle.
    mStats.trianglesScanned += mScanned;
    mStats.trianglesBounded += mBounded;
  }

 private:
  size_t at(int32_t x, int32_t y) const { return size_t(y) * mStride + x; }
  void clearSlot(size_t v, int slot) { mE[v].above[slot] = mE[v].below[slot] = 0.0f; }
  bool real(int32_t x, int32_t y) const { return !kClipped || (x <= mG.realX && y <= mG.realY); }
  bool touchesData(const BinTriangle& t) const {
    return !kClipped || (std::min({t.a.x, t.b.x, t.apex.x}) <= mG.realX &&
                         std::min({t.a.y, t.b.y, t.apex.y}) <= mG.realY);
  }
  bool risingDiagonal(int32_t x, int32_t y, int32_t h) const {
    return squareHasRisingDiagonal(mG.origin.x + x - h, mG.origin.y + y - h, 2 * h);
  }

  // E_1: the midpoint is the only sample off the triangles' corners, so |d| is exact and the
  // same for both slots.
  void smallestEdges() {
    const int32_t s = mG.side;
    for (int32_t y = 0; y <= s; ++y) {
      const bool horizontal = (y & 1) == 0;  // even rows: odd x; odd rows: even x
      const ptrdiff_t step = horizontal ? 1 : ptrdiff_t(mStride);
      for (int32_t x = horizontal ? 1 : 0; x <= s; x += 2) {
        const size_t v = at(x, y);
        if (!real(x, y)) continue;
        const double d = double(mH[v]) - 0.5 * (double(mH[v - step]) + double(mH[v + step]));
        const TriangleErrorBounds e = roundUpSides(d, 0.0, 0.0);
        mE[v] = SlotErrors{{e.above, e.above}, {e.below, e.below}};
        mA[v] = mBudget.activationFrom(std::max(e.above, e.below), 0);
      }
    }
  }

  // S_2: every sample of a slot triangle is a corner, the midpoint or a leg midpoint, and on a
  // leg the triangle's plane is the E_1 child's, so the maximum of the three is exact.
  void smallestCentres() {
    const int32_t s = mG.side;
    const ptrdiff_t w = ptrdiff_t(mStride);
    for (int32_t y = 1; y < s; y += 2) {
      for (int32_t x = 1; x < s; x += 2) {
        const size_t v = at(x, y);
        const bool rising = risingDiagonal(x, y, 1);
        const double d =
            rising ? double(mH[v]) - 0.5 * (double(mH[v - w - 1]) + double(mH[v + w + 1]))
                   : double(mH[v]) - 0.5 * (double(mH[v + w - 1]) + double(mH[v - w + 1]));
        const TriangleErrorBounds own =
            real(x, y) ? roundUpSides(d, 0.0, 0.0) : TriangleErrorBounds{};
        const float dAbove = own.above, dBelow = own.below;
        // Children: rising: slot 0 = south & east sides, slot 1 = west & north; falling:
        // slot 0 = west & south, slot 1 = north & east. E_1 slots are equal, read slot 0.
        const size_t south = v - w, north = v + w, west = v - 1, east = v + 1;
        const size_t kids[2][2] = {{rising ? south : west, rising ? east : south},
                                   {rising ? west : north, rising ? north : east}};
        uint8_t activation = std::max({mA[south], mA[north], mA[west], mA[east]});
        SlotErrors& mine = mE[v];
        for (int slot = 0; slot < 2; ++slot) {
          mine.above[slot] =
              std::max({dAbove, mE[kids[slot][0]].above[0], mE[kids[slot][1]].above[0]});
          mine.below[slot] =
              std::max({dBelow, mE[kids[slot][0]].below[0], mE[kids[slot][1]].below[0]});
          activation =
              mBudget.activationFrom(std::max(mine.above[slot], mine.below[slot]), activation);
        }
        mA[v] = activation;
      }
    }
  }

  // The bound of one slot triangle from its children, scanned exactly when the bound could
  // raise the vertex above its children's activation. Returns the vertex's activation so far.
  uint8_t slot(size_t v, int slot, double d, const Child (&kids)[2], const BinTriangle& t,
               uint8_t activation) {
    SlotErrors& mine = mE[v];
    if (!touchesData(t)) {
      mine.above[slot] = mine.below[slot] = 0.0f;
      return activation;
    }
    const SlotErrors& k0 = mE[size_t(ptrdiff_t(v) + kids[0].offset)];
    const SlotErrors& k1 = mE[size_t(ptrdiff_t(v) + kids[1].offset)];
    const TriangleErrorBounds bound =
        roundUpSides(d, double(std::max(k0.above[kids[0].slot], k1.above[kids[1].slot])),
                     double(std::max(k0.below[kids[0].slot], k1.below[kids[1].slot])));
    float above = bound.above, below = bound.below;
    if (std::max(above, below) > mBudget.thresholdAbove(activation)) {
      const TriangleErrorBounds e = scanTriangle(mH, mStride, t, mG.realX, mG.realY);
      above = e.above;
      below = e.below;
      activation = mBudget.activationFrom(std::max(above, below), activation);
      ++mScanned;
    } else {
      ++mBounded;
    }
    mine.above[slot] = above;
    mine.below[slot] = below;
    return activation;
  }

  void edges(int32_t h) {
    const int32_t s = mG.side, q = h / 2;
    const ptrdiff_t w = ptrdiff_t(mStride);
    // Horizontal: slot 0 north (children NW, NE in slot 0), slot 1 south (SW, SE in slot 1).
    const Child north[2] = {{-q + q * w, 0}, {q + q * w, 0}};
    const Child south[2] = {{-q - q * w, 1}, {q - q * w, 1}};
    // Vertical: slot 0 east (SE in slot 1, NE in slot 0), slot 1 west (SW slot 1, NW slot 0).
    const Child east[2] = {{q - q * w, 1}, {q + q * w, 0}};
    const Child west[2] = {{-q - q * w, 1}, {-q + q * w, 0}};
    for (int32_t y = 0; y <= s; y += 2 * h)
      for (int32_t x = h; x <= s; x += 2 * h) {
        const size_t v = at(x, y);
        const double d = double(mH[v]) - 0.5 * (double(mH[v - h]) + double(mH[v + h]));
        const bool up = y + h <= s, down = y - h >= 0;
        uint8_t activation = 0;
        if (up)
          activation = std::max({activation, mA[v + north[0].offset], mA[v + north[1].offset]});
        if (down)
          activation = std::max({activation, mA[v + south[0].offset], mA[v + south[1].offset]});
        const uint8_t children = activation;
        const GridPoint a{x - h, y}, b{x + h, y};
        if (up)
          activation = std::max(activation, slot(v, 0, d, north, {a, b, {x, y + h}}, children));
        else
          clearSlot(v, 0);
        if (down)
          activation = std::max(activation, slot(v, 1, d, south, {a, b, {x, y - h}}, children));
        else
          clearSlot(v, 1);
        mA[v] = activation;
      }
    for (int32_t y = h; y <= s; y += 2 * h)
      for (int32_t x = 0; x <= s; x += 2 * h) {
        const size_t v = at(x, y);
        const double d = double(mH[v]) - 0.5 * (double(mH[v - h * w]) + double(mH[v + h * w]));
        const bool right = x + h <= s, left = x - h >= 0;
        uint8_t activation = 0;
        if (right)
          activation = std::max({activation, mA[v + east[0].offset], mA[v + east[1].offset]});
        if (left)
          activation = std::max({activation, mA[v + west[0].offset], mA[v + west[1].offset]});
        const uint8_t children = activation;
        const GridPoint a{x, y - h}, b{x, y + h};
        if (right)
          activation = std::max(activation, slot(v, 0, d, east, {a, b, {x + h, y}}, children));
        else
          clearSlot(v, 0);
        if (left)
          activation = std::max(activation, slot(v, 1, d, west, {a, b, {x - h, y}}, children));
        else
          clearSlot(v, 1);
        mA[v] = activation;
      }
  }

  void centres(int32_t h) {
    const int32_t s = mG.side;
    const ptrdiff_t w = ptrdiff_t(mStride);
    const Child rising[2][2] = {{{-h * w, 0}, {h, 1}}, {{-h, 0}, {h * w, 1}}};
    const Child falling[2][2] = {{{-h, 0}, {-h * w, 0}}, {{h * w, 1}, {h, 1}}};
    for (int32_t y = h; y < s; y += 2 * h)
      for (int32_t x = h; x < s; x += 2 * h) {
        const size_t v = at(x, y);
        const GridPoint sw{x - h, y - h}, se{x + h, y - h}, nw{x - h, y + h}, ne{x + h, y + h};
        const bool r = risingDiagonal(x, y, h);
        const double d =
            r ? double(mH[v]) - 0.5 * (double(mH[at(sw.x, sw.y)]) + double(mH[at(ne.x, ne.y)]))
              : double(mH[v]) - 0.5 * (double(mH[at(nw.x, nw.y)]) + double(mH[at(se.x, se.y)]));
        const uint8_t children = std::max({mA[v - h], mA[v + h], mA[v - h * w], mA[v + h * w]});
        uint8_t activation = children;
        if (r) {
          activation = std::max(activation, slot(v, 0, d, rising[0], {sw, ne, se}, children));
          activation = std::max(activation, slot(v, 1, d, rising[1], {sw, ne, nw}, children));
        } else {
          activation = std::max(activation, slot(v, 0, d, falling[0], {nw, se, sw}, children));
          activation = std::max(activation, slot(v, 1, d, falling[1], {nw, se, ne}, children));
        }
        mA[v] = activation;
      }
  }

  const BlockGeometry& mG;
  const ErrorBudget& mBudget;
  BlockScratch& mS;
  ActivationStats& mStats;
  int32_t mStride;
  const float* mH;
  SlotErrors* mE;
  uint8_t* mA;
  uint64_t mScanned = 0;
  uint64_t mBounded = 0;
};

}  // namespace

void computeBlock(const BlockGeometry& block, const ErrorBudget& budget, BlockScratch& scratch,
                  ActivationGrid& grid, BlockResult& out, ActivationStats& stats) {
  if (block.realX < block.side || block.realY < block.side) {
    Pass<true>(block, budget, scratch, stats).run();
  } else {
    Pass<false>(block, budget, scratch, stats).run();
  }
  const int32_t s = block.side;
  const size_t stride = size_t(s) + 1;
  for (int32_t y = 0; y <= s; ++y) {
    const uint8_t* row = scratch.activation.data() + size_t(y) * stride;
    if (y == 0 || y == s) {
      for (int32_t x = 0; x <= s; ++x)
        if (row[x])
          out.border.emplace_back(GridPoint{block.origin.x + x, block.origin.y + y}, row[x]);
      continue;
    }
    if (row[0]) out.border.emplace_back(GridPoint{block.origin.x, block.origin.y + y}, row[0]);
    if (row[s]) out.border.emplace_back(GridPoint{block.origin.x + s, block.origin.y + y}, row[s]);
    grid.setRun(block.origin.x + 1, block.origin.y + y, row + 1, s - 1);
  }
  const SlotErrors& c = scratch.slots[size_t(s / 2) * stride + s / 2];
  for (int slot = 0; slot < 2; ++slot) out.squareErrors[slot] = {c.above[slot], c.below[slot]};
  out.computed = true;
}

}  // namespace terralod
