#include "terralod/core/bintree.h"

#include <gtest/gtest.h>

#include <set>

namespace terralod {
namespace {

constexpr int32_t kSide = 64;

bool sameTriangle(const BinTriangle& a, const BinTriangle& b) {
  auto key = [](const BinTriangle& t) {
    std::set<std::pair<int32_t, int32_t>> s{{t.a.x, t.a.y}, {t.b.x, t.b.y}, {t.apex.x, t.apex.y}};
    return s;
  };
  return key(a) == key(b) && a.apex == b.apex;
}

TEST(Bintree, ClassifiesCornersEdgesAndCentres) {
  EXPECT_EQ(classifyVertex(0, 0, kSide).kind, VertexKind::kCorner);
  EXPECT_EQ(classifyVertex(kSide, kSide, kSide).kind, VertexKind::kCorner);
  const VertexClass center = classifyVertex(32, 32, kSide);
  EXPECT_EQ(center.kind, VertexKind::kSquareCenter);
  EXPECT_EQ(center.half, 32);
  const VertexClass south = classifyVertex(32, 0, kSide);
  EXPECT_EQ(south.kind, VertexKind::kEdgeMidpoint);
  EXPECT_TRUE(south.horizontal);
  EXPECT_EQ(south.half, 32);
  const VertexClass east = classifyVertex(kSide, 32, kSide);
  EXPECT_EQ(east.kind, VertexKind::kEdgeMidpoint);
  EXPECT_FALSE(east.horizontal);
  const VertexClass small = classifyVertex(3, 5, kSide);
  EXPECT_EQ(small.kind, VertexKind::kSquareCenter);
  EXPECT_EQ(small.half, 1);
}

// Every slot triangle of every vertex: its hypotenuse midpoint is the vertex, and its two
// children are exactly the slots childSlots() names.
TEST(Bintree, ChildSlotsMatchGenericSplit) {
  int checked = 0;
  for (int32_t y = 0; y <= kSide; ++y) {
    for (int32_t x = 0; x <= kSide; ++x) {
      const VertexClass c = classifyVertex(x, y, kSide);
      if (c.kind == VertexKind::kCorner) continue;
      const GridPoint v{x, y};
      const auto tris = diamondTriangles(v, c);
      const bool rising = c.kind == VertexKind::kSquareCenter &&
                          squareHasRisingDiagonal(x - c.half, y - c.half, 2 * c.half);
      for (int s = 0; s < 2; ++s) {
        const BinTriangle& t = tris[s];
        ASSERT_EQ(t.hypotenuseMidpoint(), v);
        if (!insideGrid(t, kSide, kSide)) continue;
        if (c.kind == VertexKind::kEdgeMidpoint && c.half < 2) continue;
        const auto kids = t.children();
        const auto slots = childSlots(c, rising, s);
        for (int k = 0; k < 2; ++k) {
          const GridPoint childVertex{x + slots[k].dx, y + slots[k].dy};
          const VertexClass cc = classifyVertex(childVertex.x, childVertex.y, kSide);
          const BinTriangle named = diamondTriangles(childVertex, cc)[slots[k].slot];
          ASSERT_TRUE(sameTriangle(named, kids[k]))
              << "vertex " << x << "," << y << " slot " << s << " child " << k;
          ++checked;
        }
      }
    }
  }
  EXPECT_GT(checked, 8000);  // every slot of a 64x64 grid below the corners
}

// A vertex's dependency parents are exactly the vertices that list it as a child.
TEST(Bintree, DependencyParentsInvertChildSlots) {
  std::set<std::tuple<int32_t, int32_t, int32_t, int32_t>> childOf;  // (child, parent)
  for (int32_t y = 0; y <= kSide; ++y)
    for (int32_t x = 0; x <= kSide; ++x) {
      const VertexClass c = classifyVertex(x, y, kSide);
      if (c.kind == VertexKind::kCorner || (c.kind == VertexKind::kEdgeMidpoint && c.half < 2))
        continue;
      const bool rising = c.kind == VertexKind::kSquareCenter &&
                          squareHasRisingDiagonal(x - c.half, y - c.half, 2 * c.half);
      const auto tris = diamondTriangles({x, y}, c);
      for (int s = 0; s < 2; ++s) {
        if (!insideGrid(tris[s], kSide, kSide)) continue;
        for (const ChildSlot& k : childSlots(c, rising, s))
          childOf.insert({x + k.dx, y + k.dy, x, y});
      }
    }
  for (int32_t y = 0; y <= kSide; ++y)
    for (int32_t x = 0; x <= kSide; ++x) {
      const VertexClass c = classifyVertex(x, y, kSide);
      if (c.kind == VertexKind::kCorner || c.half >= kSide / 2) continue;
      for (const GridPoint p : dependencyParents({x, y}, c)) {
        if (!insideGrid(p, kSide, kSide)) continue;
        EXPECT_TRUE(childOf.count({x, y, p.x, p.y}))
            << x << "," << y << " -> " << p.x << "," << p.y;
      }
    }
}

TEST(Bintree, SquareTrianglesAreNestedInTheirParentSquare) {
  // Each quadrant's two triangles lie inside one of the parent's triangles or their children.
  for (int32_t side = 2; side <= kSide; side *= 2) {
    for (int32_t y0 = 0; y0 + 2 * side <= kSide; y0 += 2 * side)
      for (int32_t x0 = 0; x0 + 2 * side <= kSide; x0 += 2 * side) {
        std::vector<BinTriangle> level;
        for (const BinTriangle& t : squareTriangles(x0, y0, 2 * side))
          for (const BinTriangle& c : t.children())
            for (const BinTriangle& g : c.children()) level.push_back(g);
        for (int q = 0; q < 4; ++q) {
          const int32_t qx = x0 + (q & 1) * side, qy = y0 + (q >> 1) * side;
          for (const BinTriangle& t : squareTriangles(qx, qy, side)) {
            bool found = false;
            for (const BinTriangle& g : level) found |= sameTriangle(g, t);
            EXPECT_TRUE(found) << "quadrant " << qx << "," << qy << " side " << side;
          }
        }
      }
  }
}

TEST(Bintree, ChildContainingFindsThePoint) {
  const BinTriangle t = squareTriangles(0, 0, 16)[0];
  for (int32_t y = 0; y <= 16; ++y)
    for (int32_t x = 0; x <= 16; ++x) {
      const GridPoint p{x, y};
      auto inside = [&](const BinTriangle& u) {
        const int64_t d1 = orient2d(u.a, u.b, p), d2 = orient2d(u.b, u.apex, p),
                      d3 = orient2d(u.apex, u.a, p);
        return !((d1 < 0 || d2 < 0 || d3 < 0) && (d1 > 0 || d2 > 0 || d3 > 0));
      };
      if (!inside(t)) continue;
      EXPECT_TRUE(inside(t.children()[childContaining(t, p)])) << x << "," << y;
    }
}

}  // namespace
}  // namespace terralod
