#pragma once
// Addressing of the right-triangulated irregular network (RTIN) over a square grid whose side
// is a power of two. Every grid point except the square's corners is the midpoint of the
// hypotenuse of one or two right isosceles triangles (its "diamond"); splitting a triangle at
// that midpoint yields two children. Squares of side a with lower-left corner (i*a, j*a) are
// cut along the "/" diagonal when i+j is even and along "\" otherwise, which makes the
// hierarchy nested: every square of the quadtree is exactly two bintree triangles.
// All functions are pure and integer-exact.

#include <array>
#include <bit>
#include <cassert>
#include <cstdint>

namespace terralod {

struct GridPoint {
  int32_t x = 0;
  int32_t y = 0;
  friend bool operator==(GridPoint, GridPoint) = default;
};

/// A triangle of the bintree: hypotenuse a-b, right angle at apex. Counter-clockwise
/// orientation is not guaranteed; use orientTriangle() when emitting.
struct BinTriangle {
  GridPoint a;
  GridPoint b;
  GridPoint apex;
  GridPoint hypotenuseMidpoint() const { return {(a.x + b.x) / 2, (a.y + b.y) / 2}; }
  /// True when the hypotenuse midpoint is a grid point, i.e. the triangle can be split.
  bool splittable() const { return ((a.x + b.x) % 2 == 0) && ((a.y + b.y) % 2 == 0); }
  /// The two children after splitting at the hypotenuse midpoint.
  std::array<BinTriangle, 2> children() const {
    GridPoint m = hypotenuseMidpoint();
    return {BinTriangle{apex, a, m}, BinTriangle{b, apex, m}};
  }
};

enum class VertexKind : uint8_t {
  kCorner,        ///< a corner of the whole grid square; never split from anything
  kEdgeMidpoint,  ///< midpoint of an axis-aligned hypotenuse of length 2*half
  kSquareCenter,  ///< centre of an axis-aligned square of side 2*half (diagonal hypotenuse)
};

struct VertexClass {
  VertexKind kind = VertexKind::kCorner;
  int32_t half = 0;         ///< half the hypotenuse length along an axis
  bool horizontal = false;  ///< edge midpoints: the hypotenuse runs along x
};

/// Classifies grid point (x, y) of a grid of side `gridSide` (a power of two).
inline VertexClass classifyVertex(int32_t x, int32_t y, int32_t gridSide) {
  const int big = std::countr_zero(static_cast<uint32_t>(gridSide)) + 1;
  const int tx = x == 0 ? big : std::countr_zero(static_cast<uint32_t>(x));
  const int ty = y == 0 ? big : std::countr_zero(static_cast<uint32_t>(y));
  if (tx >= big - 1 && ty >= big - 1) return {VertexKind::kCorner, gridSide, false};
  if (tx == ty) return {VertexKind::kSquareCenter, int32_t{1} << tx, false};
  const int t = tx < ty ? tx : ty;
  return {VertexKind::kEdgeMidpoint, int32_t{1} << t, tx < ty};
}

/// True when the square of side `side` with lower-left corner (x0, y0) is cut along "/".
inline bool squareHasRisingDiagonal(int32_t x0, int32_t y0, int32_t side) {
  return ((x0 / side + y0 / side) & 1) == 0;
}

/// The two triangles of a square cut along "/" (`rising`) or "\\" (slot 0, slot 1).
inline std::array<BinTriangle, 2> squareTriangles(int32_t x0, int32_t y0, int32_t side,
                                                  bool rising) {
  const GridPoint sw{x0, y0}, se{x0 + side, y0}, nw{x0, y0 + side}, ne{x0 + side, y0 + side};
  if (rising) return {BinTriangle{sw, ne, se}, BinTriangle{sw, ne, nw}};
  return {BinTriangle{nw, se, sw}, BinTriangle{nw, se, ne}};
}

/// The two triangles of an axis-aligned square of the hierarchy (slot 0, slot 1).
inline std::array<BinTriangle, 2> squareTriangles(int32_t x0, int32_t y0, int32_t side) {
  return squareTriangles(x0, y0, side, squareHasRisingDiagonal(x0, y0, side));
}

/// The (up to) two triangles whose hypotenuse midpoint is v. Slot order is fixed:
/// horizontal edge: north, south; vertical edge: east, west; square centre: as squareTriangles.
/// Triangles may extend outside the grid; callers check with insideGrid().
inline std::array<BinTriangle, 2> diamondTriangles(GridPoint v, const VertexClass& c) {
  const int32_t h = c.half;
  if (c.kind == VertexKind::kSquareCenter) return squareTriangles(v.x - h, v.y - h, 2 * h);
  if (c.horizontal) {
    const GridPoint w{v.x - h, v.y}, e{v.x + h, v.y};
    return {BinTriangle{w, e, {v.x, v.y + h}}, BinTriangle{w, e, {v.x, v.y - h}}};
  }
  const GridPoint s{v.x, v.y - h}, n{v.x, v.y + h};
  return {BinTriangle{s, n, {v.x + h, v.y}}, BinTriangle{s, n, {v.x - h, v.y}}};
}

/// The grid points whose diamonds have a leg through v: the vertices that must be split
/// before v can be (its "parents" in the RTIN dependency graph). Either may be outside the grid.
inline std::array<GridPoint, 2> dependencyParents(GridPoint v, const VertexClass& c) {
  const int32_t h = c.half;
  if (c.kind == VertexKind::kEdgeMidpoint) {
    if (c.horizontal) return {GridPoint{v.x, v.y + h}, GridPoint{v.x, v.y - h}};
    return {GridPoint{v.x + h, v.y}, GridPoint{v.x - h, v.y}};
  }
  // Square centre: the two corners of its square that are not on its diagonal.
  if (squareHasRisingDiagonal(v.x - h, v.y - h, 2 * h))
    return {GridPoint{v.x + h, v.y - h}, GridPoint{v.x - h, v.y + h}};
  return {GridPoint{v.x - h, v.y - h}, GridPoint{v.x + h, v.y + h}};
}

/// A child triangle of a diamond slot: it is slot `slot` of the vertex at offset (dx, dy).
struct ChildSlot {
  int32_t dx = 0, dy = 0;
  int slot = 0;
};

/// The two children of slot `slot` of vertex class `c` (half >= 2 for edge midpoints), as
/// slots of the vertices at the midpoints of its legs. `rising` is the square centre's
/// diagonal (squareHasRisingDiagonal of its square); ignored for edge midpoints. These follow
/// from the diagonal rule and are checked against diamondTriangles()/children() in the tests.
inline std::array<ChildSlot, 2> childSlots(const VertexClass& c, bool rising, int slot) {
  const int32_t h = c.half;
  if (c.kind == VertexKind::kSquareCenter) {
    if (rising) {
      if (slot == 0) return {ChildSlot{0, -h, 0}, ChildSlot{h, 0, 1}};
      return {ChildSlot{-h, 0, 0}, ChildSlot{0, h, 1}};
    }
    if (slot == 0) return {ChildSlot{-h, 0, 0}, ChildSlot{0, -h, 0}};
    return {ChildSlot{0, h, 1}, ChildSlot{h, 0, 1}};
  }
  const int32_t q = h / 2;
  if (c.horizontal) {
    if (slot == 0) return {ChildSlot{-q, q, 0}, ChildSlot{q, q, 0}};  // north triangle
    return {ChildSlot{-q, -q, 1}, ChildSlot{q, -q, 1}};               // south triangle
  }
  if (slot == 0) return {ChildSlot{q, -q, 1}, ChildSlot{q, q, 0}};  // east triangle
  return {ChildSlot{-q, -q, 1}, ChildSlot{-q, q, 0}};               // west triangle
}

inline bool insideGrid(GridPoint p, int32_t sizeX, int32_t sizeY) {
  return p.x >= 0 && p.y >= 0 && p.x <= sizeX && p.y <= sizeY;
}

inline bool insideGrid(const BinTriangle& t, int32_t sizeX, int32_t sizeY) {
  return insideGrid(t.a, sizeX, sizeY) && insideGrid(t.b, sizeX, sizeY) &&
         insideGrid(t.apex, sizeX, sizeY);
}

/// Twice the signed area of (a, b, c): positive when counter-clockwise.
inline int64_t orient2d(GridPoint a, GridPoint b, GridPoint c) {
  return int64_t(b.x - a.x) * (c.y - a.y) - int64_t(b.y - a.y) * (c.x - a.x);
}

/// Which child of `t` contains point p (0 or 1); points on the split line go to child 0.
inline int childContaining(const BinTriangle& t, GridPoint p) {
  const GridPoint m = t.hypotenuseMidpoint();
  const int64_t sideP = orient2d(t.apex, m, p);
  const int64_t sideA = orient2d(t.apex, m, t.a);
  return (sideP == 0 || (sideP > 0) == (sideA > 0)) ? 0 : 1;
}

/// Clips the convex polygon `poly` (n corners; room for 8) to x <= limit (`alongX`) or
/// y <= limit, Sutherland-Hodgman in corner order. Bintree edges are axis-aligned or diagonal,
/// so every crossing of a grid line is itself a grid point. A corner is anything with a
/// GridPoint `p`; `between(a, b, f)` makes the crossing at fraction f from a to b, whose `p`
/// is then set.
template <typename Corner, typename Between>
void clipToLine(Corner (&poly)[8], int& n, bool alongX, int32_t limit, Between&& between) {
  Corner out[8];
  int m = 0;
  for (int i = 0; i < n; ++i) {
    const Corner& a = poly[i];
    const Corner& b = poly[(i + 1) % n];
    const int32_t ac = alongX ? a.p.x : a.p.y, bc = alongX ? b.p.x : b.p.y;
    if (ac <= limit) out[m++] = a;
    if (int64_t(ac - limit) * (bc - limit) < 0) {
      const int32_t ao = alongX ? a.p.y : a.p.x, bo = alongX ? b.p.y : b.p.x;
      assert((int64_t(limit - ac) * (bo - ao)) % (bc - ac) == 0);
      const int32_t other = ao + int32_t(int64_t(limit - ac) * (bo - ao) / (bc - ac));
      Corner c = between(a, b, double(limit - ac) / double(bc - ac));
      c.p = alongX ? GridPoint{limit, other} : GridPoint{other, limit};
      out[m++] = c;
    }
  }
  n = m;
  for (int i = 0; i < m; ++i) poly[i] = out[i];
}

}  // namespace terralod
