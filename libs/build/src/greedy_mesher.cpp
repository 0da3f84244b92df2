#include "terralod/build/greedy_mesher.h"

#include "terralod/core/sample_raster.h"

#include <meshoptimizer.h>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <map>
#include <queue>

namespace terralod {
namespace {

struct Point {
  int32_t x = 0, y = 0;
  bool operator==(const Point&) const = default;
};

int64_t orient(int64_t ax, int64_t ay, int64_t bx, int64_t by, int64_t cx, int64_t cy) {
  return (bx - ax) * (cy - ay) - (by - ay) * (cx - ax);
}
int64_t orient(Point a, Point b, Point c) {
  return orient(a.x, a.y, b.x, b.y, c.x, c.y);
}

// > 0 when d lies inside the circle through the counter-clockwise triangle a, b, c.
bool inCircle(Point a, Point b, Point c, Point d) {
  const __int128 adx = a.x - d.x, ady = a.y - d.y, bdx = b.x - d.x, bdy = b.y - d.y,
                 cdx = c.x - d.x, cdy = c.y - d.y;
  const __int128 ad = adx * adx + ady * ady, bd = bdx * bdx + bdy * bdy, cd = cdx * cdx + cdy * cdy;
  const __int128 det =
      adx * (bdy * cd - bd * cdy) - ady * (bdx * cd - bd * cdx) + ad * (bdx * cdy - bdy * cdx);
  return det > 0;
}

constexpr int32_t next(int32_t e) {
  return e % 3 == 2 ? e - 2 : e + 1;
}
constexpr int32_t prev(int32_t e) {
  return e % 3 == 0 ? e + 2 : e - 1;
}

// A convex polygon: a triangle cut by up to four lines has at most seven corners.
struct Polygon {
  Point p[8];
  size_t size = 0;
  void push(Point q) { p[size++] = q; }
};

// Clips a convex polygon to one side of an axis-aligned line; false when a crossing is not a
// grid point.
bool clip(Polygon& poly, bool alongX, int32_t limit, bool keepBelow) {
  Polygon out;
  const size_t n = poly.size;
  for (size_t i = 0; i < n; ++i) {
    const Point p = poly.p[i], q = poly.p[(i + 1) % n];
    const int64_t pc = alongX ? p.x : p.y, qc = alongX ? q.x : q.y;
    const bool pIn = keepBelow ? pc <= limit : pc >= limit;
    const bool qIn = keepBelow ? qc <= limit : qc >= limit;
    if (pIn) out.push(p);
    if (pIn != qIn && pc != limit && qc != limit) {
      const int64_t po = alongX ? p.y : p.x, qo = alongX ? q.y : q.x;
      const int64_t num = (limit - pc) * (qo - po), den = qc - pc;
      if (num % den != 0) return false;
      const auto other = int32_t(po + num / den);
      out.push(alongX ? Point{limit, other} : Point{other, limit});
    }
  }
  poly.size = 0;
  for (size_t i = 0; i < out.size; ++i)
    if (poly.size == 0 || !(poly.p[poly.size - 1] == out.p[i])) poly.push(out.p[i]);
  while (poly.size > 1 && poly.p[0] == poly.p[poly.size - 1]) --poly.size;
  return true;
}

class Mesher {
 public:
  explicit Mesher(const GreedyMeshInput& in)
      : mIn(in), mStride(size_t(in.width) + 1), mPointIndex(in.heights.size(), -1) {}

  bool run(GreedyMesh& out) {
    const bool fromVertices =
        mIn.start != GreedyStart::kParentTriangles && morphs() && mIn.verticesMorph;
    if (!(fromVertices ? seedFromVertices() : seed()) || mDegenerate) return false;
    for (int side = 0; side < 4; ++side) refineSide(side);
    mRefining = -1;
    for (int32_t t = 0; t < triangleCount(); ++t) evaluate(t);
    while (!mQueue.empty()) {
      const Entry top = mQueue.top();
      mQueue.pop();
      if (top.serial != mSerial[size_t(top.triangle)]) continue;  // stale
      insertCandidate(top.triangle);
    }
    simplify();
    if (mIn.vertexHeights == VertexHeights::kFitted) {
      recentre();
      simplify();
    }
    out = ordered();
    return true;
  }

 private:
  struct Entry {
    double violation;
    int32_t triangle;
    uint32_t serial;
    bool operator<(const Entry& o) const {
      return violation != o.violation ? violation < o.violation : triangle > o.triangle;
    }
  };

  size_t sample(int32_t x, int32_t y) const { return size_t(y) * mStride + size_t(x); }
  double height(int32_t p) const { return mZ[size_t(p)]; }
  int32_t triangleCount() const { return int32_t(mV.size() / 3); }
  Point at(int32_t e) const { return mP[size_t(mV[size_t(e)])]; }

  int32_t pointIndex(Point p) {
    int32_t& slot = mPointIndex[sample(p.x, p.y)];
    if (slot < 0) {
      slot = int32_t(mP.size());
      mP.push_back(p);
      mZ.push_back(mIn.heights[sample(p.x, p.y)]);
    }
    return slot;
  }
  int32_t addTriangle(int32_t a, int32_t b, int32_t c) {
    mV.insert(mV.end(), {a, b, c});
    mOpp.insert(mOpp.end(), {-1, -1, -1});
    mFixed.insert(mFixed.end(),
                  {kindOf(mP[size_t(a)], mP[size_t(b)]), kindOf(mP[size_t(b)], mP[size_t(c)]),
                   kindOf(mP[size_t(c)], mP[size_t(a)])});
    mSerial.push_back(0);
    mCandidate.push_back(-1);
    mTouched.push_back(triangleCount() - 1);
    return triangleCount() - 1;
  }
  void setTriangle(int32_t t, int32_t a, int32_t b, int32_t c) {
    mV[3 * size_t(t)] = a;
    mV[3 * size_t(t) + 1] = b;
    mV[3 * size_t(t) + 2] = c;
    ++mSerial[size_t(t)];
    mTouched.push_back(t);
  }
  // Makes e the twin of f (f < 0: a boundary), with the edge's fixedness.
  void link(int32_t e, int32_t f, uint8_t fixed) {
    mOpp[size_t(e)] = f;
    mFixed[size_t(e)] = fixed;
    if (f >= 0) {
      mOpp[size_t(f)] = e;
      mFixed[size_t(f)] = fixed;
    }
  }
  // Edge kinds: free (flips towards Delaunay), a parent's edge (flips only within the gap),
  // a line's or a side's (never flips).
  static constexpr uint8_t kFree = 0, kParentEdge = 1, kLine = 2;
  uint8_t kindOf(Point a, Point b) const {
    const int32_t s = mIn.lineSpacing > 0 ? mIn.lineSpacing : std::max(mIn.width, mIn.height);
    const bool onLine = (a.x == b.x && (a.x % s == 0 || a.x == mIn.width)) ||
                        (a.y == b.y && (a.y % s == 0 || a.y == mIn.height));
    return onLine ? kLine : kParentEdge;
  }
  bool morphs() const { return !mIn.parentHeights.empty(); }
  // Whether every triangle must keep to the gap with its vertices on the parent's surface.
  bool gapHolds() const { return morphs() && mIn.gap > 0.0 && mIn.verticesMorph; }

  // The parent's triangles cut along the rectangle and the lines, each piece fanned; edges
  // inside a piece may flip, the pieces' own may not.
  bool seed() {
    const int32_t w = mIn.width, h = mIn.height;
    const int32_t s = mIn.lineSpacing > 0 ? mIn.lineSpacing : std::max(w, h);
    Polygon poly;
    for (size_t k = 0; k + 2 < mIn.parent.size(); k += 3) {
      Point c[3];
      for (int i = 0; i < 3; ++i) c[i] = {mIn.parent[k + size_t(i)].x, mIn.parent[k + size_t(i)].y};
      const int64_t area = orient(c[0], c[1], c[2]);
      if (area == 0) continue;
      if (area < 0) std::swap(c[1], c[2]);
      const int32_t x0 = std::max(0, std::min({c[0].x, c[1].x, c[2].x}));
      const int32_t x1 = std::min(w, std::max({c[0].x, c[1].x, c[2].x}));
      const int32_t y0 = std::max(0, std::min({c[0].y, c[1].y, c[2].y}));
      const int32_t y1 = std::min(h, std::max({c[0].y, c[1].y, c[2].y}));
      if (x0 >= x1 || y0 >= y1) continue;
      const int32_t minX = std::min({c[0].x, c[1].x, c[2].x}),
                    maxX = std::max({c[0].x, c[1].x, c[2].x}),
                    minY = std::min({c[0].y, c[1].y, c[2].y}),
                    maxY = std::max({c[0].y, c[1].y, c[2].y});
      if (minX >= 0 && minY >= 0 && maxX <= w && maxY <= h && minX / s == (maxX - 1) / s &&
          minY / s == (maxY - 1) / s) {  // inside one cell: nothing to cut
        poly.size = 0;
        for (const Point& q : c) poly.push(q);
        fan(poly);
        continue;
      }
      for (int32_t cy = y0 / s * s; cy < y1; cy += s)
        for (int32_t cx = x0 / s * s; cx < x1; cx += s) {
          poly.size = 0;
          for (const Point& q : c) poly.push(q);
          if (!clip(poly, true, cx, false) || !clip(poly, true, std::min(cx + s, w), true) ||
              !clip(poly, false, cy, false) || !clip(poly, false, std::min(cy + s, h), true))
            return false;
          if (poly.size >= 3) fan(poly);
        }
    }
    // Twins by their end points: half-edges sorted by (lower end, upper end), a pair of
    // twins side by side.
    std::vector<std::pair<uint64_t, int32_t>> halfEdges;
    halfEdges.reserve(mV.size());
    for (int32_t e = 0; e < int32_t(mV.size()); ++e) {
      const auto a = uint32_t(mV[size_t(e)]), b = uint32_t(mV[size_t(next(e))]);
      halfEdges.emplace_back((uint64_t(std::min(a, b)) << 32) | std::max(a, b), e);
    }
    std::sort(halfEdges.begin(), halfEdges.end());
    for (size_t i = 0; i + 1 < halfEdges.size(); ++i)
      if (halfEdges[i].first == halfEdges[i + 1].first) {
        const int32_t e = halfEdges[i].second, f = halfEdges[i + 1].second;
        link(e, f, std::max(mFixed[size_t(e)], mFixed[size_t(f)]));
        ++i;
      }
    mTouched.clear();
    return triangleCount() > 0;
  }

  // The rectangle as two triangles, then every parent vertex in it (its sides included)
  // inserted as insertion inserts a sample, then (GreedyStart::kParentVerticesAndEdges) each
  // parent edge with both ends in it made an edge again by flips and fixed, as the parent's
  // edges are in seed(). The parent's edges that leave the rectangle are not kept, so triangles
  // may lie across the parent's: evaluate() measures the gap of each, and insertion mends it
  // where it is broken.
  bool seedFromVertices() {
    const int32_t w = mIn.width, h = mIn.height;
    const int32_t a = pointIndex({0, 0}), b = pointIndex({w, 0}), c = pointIndex({w, h}),
                  d = pointIndex({0, h});
    addTriangle(a, b, c);
    addTriangle(a, c, d);
    link(2, 3, kFree);  // the diagonal
    mTouched.clear();
    mSeeding = true;  // run() evaluates every triangle once the sides are in
    auto inside = [&](const SurfaceCorner& p) {
      return p.x >= 0 && p.y >= 0 && p.x <= w && p.y <= h;
    };
    int32_t hint = 0;
    for (const SurfaceCorner& p : mIn.parent) {
      if (!inside(p) || mPointIndex[sample(p.x, p.y)] >= 0) continue;
      const int32_t t = locate({p.x, p.y}, hint);
      if (t < 0) continue;
      hint = t;
      mCandidate[size_t(t)] = int32_t(sample(p.x, p.y));
      insertCandidate(t);
    }
    if (mIn.start == GreedyStart::kParentVerticesAndEdges) {
      mIncident.assign(mP.size(), -1);
      for (int32_t e = 0; e < int32_t(mV.size()); ++e) mIncident[size_t(mV[size_t(e)])] = e;
      for (size_t k = 0; k + 2 < mIn.parent.size(); k += 3)
        for (size_t i = 0; i < 3; ++i) {
          const SurfaceCorner& p = mIn.parent[k + i];
          const SurfaceCorner& q = mIn.parent[k + (i + 1) % 3];
          const bool alongSide =
              (p.x == q.x && (p.x == 0 || p.x == w)) || (p.y == q.y && (p.y == 0 || p.y == h));
          if (inside(p) && inside(q) && !alongSide)
            recoverEdge(mPointIndex[sample(p.x, p.y)], mPointIndex[sample(q.x, q.y)]);
        }
      mIncident.clear();  // insertion does not keep it
    }
    mTouched.clear();
    mSeeding = false;
    return true;
  }

  // Flips edges across segment a-b until it is an edge, then fixes it as a parent's edge. Gives
  // up (leaving the gap to insertion) where a fixed edge or a vertex lies across it.
  void recoverEdge(int32_t a, int32_t b) {
    const Point pa = mP[size_t(a)], pb = mP[size_t(b)];
    for (int attempt = 0; attempt < 4096; ++attempt) {
      // The triangle around a that b lies beyond: a -> s on the right of a -> b, t on its left.
      int32_t cross = -1;
      bool found = false;
      forEachAround(a, [&](int32_t e) {
        if (found || cross >= 0) return;
        const int32_t s = mV[size_t(next(e))], t = mV[size_t(prev(e))];
        if (s == b || t == b) {
          const int32_t edge = s == b ? e : prev(e);
          mFixed[size_t(edge)] = kParentEdge;
          if (mOpp[size_t(edge)] >= 0) mFixed[size_t(mOpp[size_t(edge)])] = kParentEdge;
          found = true;
          return;
        }
        if (orient(pa, pb, mP[size_t(s)]) < 0 && orient(pa, pb, mP[size_t(t)]) > 0) cross = next(e);
      });
      if (found || cross < 0) return;
      // Along the corridor: flip the first crossed edge whose quadrilateral is convex.
      bool flipped = false;
      for (int steps = 0; steps < 4096 && !flipped; ++steps) {
        const int32_t g = mOpp[size_t(cross)];
        if (g < 0 || mFixed[size_t(cross)] != kFree) return;
        const int32_t s = mV[size_t(cross)], t = mV[size_t(next(cross))],
                      o = mV[size_t(prev(cross))], r = mV[size_t(prev(g))];
        const Point ps = mP[size_t(s)], pt = mP[size_t(t)], po = mP[size_t(o)], pr = mP[size_t(r)];
        if (orient(po, pr, ps) < 0 && orient(po, pr, pt) > 0) {
          flip(cross);
          flipped = true;
          break;
        }
        if (r == b) return;  // the last one, not flippable now: give up
        const int64_t side = orient(pa, pb, pr);
        if (side == 0) return;  // a vertex on the segment
        cross = side > 0 ? next(g) : prev(g);
      }
      if (!flipped) return;
    }
  }

  // Calls f(e) for each half-edge out of u (both ways round from mIncident, u may be on a side).
  template <typename F>
  void forEachAround(int32_t u, F&& f) const {
    const int32_t first = mIncident[size_t(u)];
    if (walkOutgoing(first, f)) return;
    int32_t e = first;  // the rest, clockwise
    for (int steps = 0; steps < kMaxDegree; ++steps) {
      const int32_t o = mOpp[size_t(e)];
      if (o < 0) return;
      e = next(o);
      if (e == first) return;
      f(e);
    }
  }

  // Flips edge e = (a -> b) of T = (a, b, p) with its twin in U = (b, a, q): T = (p, a, q),
  // U = (q, b, p); links, fixedness, the sides' index and mIncident (while kept) follow.
  void flip(int32_t e) {
    const int32_t f = mOpp[size_t(e)];
    const int32_t T = e / 3, U = f / 3;
    const int32_t a = mV[size_t(e)], b = mV[size_t(next(e))], p = mV[size_t(prev(e))];
    const int32_t q = mV[size_t(prev(f))];
    const int32_t x1 = mOpp[size_t(next(e))], x2 = mOpp[size_t(prev(e))];
    const int32_t y1 = mOpp[size_t(next(f))], y2 = mOpp[size_t(prev(f))];
    const uint8_t f1 = mFixed[size_t(next(e))], f2 = mFixed[size_t(prev(e))];
    const uint8_t g1 = mFixed[size_t(next(f))], g2 = mFixed[size_t(prev(f))];
    setTriangle(T, p, a, q);
    setTriangle(U, q, b, p);
    link(3 * T, x2, f2);
    link(3 * T + 1, y1, g1);
    link(3 * T + 2, 3 * U + 2, kFree);
    link(3 * U, y2, g2);
    link(3 * U + 1, x1, f1);
    if (y1 < 0) addSideEdge(3 * T + 1);
    if (y2 < 0) addSideEdge(3 * U);
    if (x1 < 0) addSideEdge(3 * U + 1);
    if (x2 < 0) addSideEdge(3 * T);
    if (!mIncident.empty()) {
      mIncident[size_t(p)] = 3 * T;
      mIncident[size_t(a)] = 3 * T + 1;
      mIncident[size_t(q)] = 3 * U;
      mIncident[size_t(b)] = 3 * U + 1;
    }
  }

  // A triangle holding p (inside or on its edges), walking from triangle `from` towards p
  // across the edge p lies beyond (Lawson's walk, which ends in a Delaunay triangulation);
  // every triangle in turn if it goes on for too long; -1 for a point outside the rectangle.
  int32_t locate(Point p, int32_t from) const {
    int32_t t = std::min(from, triangleCount() - 1);
    for (int32_t steps = 0; steps < triangleCount(); ++steps) {
      int32_t across = -1;
      for (int i = 0; i < 3 && across < 0; ++i) {
        const int32_t e = 3 * t + i;
        if (orient(at(e), at(next(e)), p) < 0) across = mOpp[size_t(e)];
      }
      if (across < 0) {
        bool inside = true;
        for (int i = 0; i < 3; ++i)
          inside = inside && orient(at(3 * t + i), at(next(3 * t + i)), p) >= 0;
        if (inside) return t;
        break;  // beyond the rectangle's side: cannot be for points inside it
      }
      t = across / 3;
    }
    for (t = 0; t < triangleCount(); ++t)
      if (orient(at(3 * t), at(3 * t + 1), p) >= 0 &&
          orient(at(3 * t + 1), at(3 * t + 2), p) >= 0 && orient(at(3 * t + 2), at(3 * t), p) >= 0)
        return t;
    return -1;  // outside the rectangle: not for points in it
  }

  // Triangulates a convex piece as a fan from the first corner that gives no flat triangle.
  void fan(const Polygon& poly) {
    const size_t n = poly.size;
    for (size_t start = 0; start < n; ++start) {
      bool ok = true;
      for (size_t i = 1; ok && i + 1 < n; ++i)
        ok = orient(poly.p[start], poly.p[(start + i) % n], poly.p[(start + i + 1) % n]) > 0;
      if (!ok) continue;
      int32_t ids[8];
      for (size_t i = 0; i < n; ++i) ids[i] = pointIndex(poly.p[(start + i) % n]);
      for (size_t i = 1; i + 1 < n; ++i) {
        const int32_t t = addTriangle(ids[0], ids[i], ids[i + 1]);
        if (i > 1) mFixed[3 * size_t(t)] = 0;          // diagonal back to the start
        if (i + 2 < n) mFixed[3 * size_t(t) + 2] = 0;  // diagonal to the next triangle
      }
      return;
    }
    mDegenerate = true;  // not convex: run() refuses the parent (an internal error upstream)
  }

  // Boundary half-edges on the rectangle's sides, by side and lower end along it.
  int sideOf(Point a, Point b) const {
    if (a.y == 0 && b.y == 0) return 0;
    if (a.x == mIn.width && b.x == mIn.width) return 1;
    if (a.y == mIn.height && b.y == mIn.height) return 2;
    if (a.x == 0 && b.x == 0) return 3;
    return -1;
  }
  void addSideEdge(int32_t e) {
    const Point a = at(e), b = at(next(e));
    const int side = sideOf(a, b);
    if (side < 0 || side != mRefining) return;
    const bool alongX = side == 0 || side == 2;
    mSides[side][std::min(alongX ? a.x : a.y, alongX ? b.x : b.y)] = e;
  }

  double violation(size_t s, double z) const { return std::fabs(z - mIn.heights[s]) - mIn.error; }
  double gapViolation(size_t s, double zp) const {
    return std::max(std::fabs(zp - mIn.parentHeights[s]) - mIn.gap,
                    std::fabs(zp - mIn.heights[s]) - mIn.parentError);
  }
  double parentAt(int32_t p) const {
    return mIn.parentHeights[sample(mP[size_t(p)].x, mP[size_t(p)].y)];
  }

  // One side alone: its vertices so far (the parent's and the pieces' corners), refined by
  // greedy insertion along the line, then split into the triangulation.
  void refineSide(int side) {
    const int32_t w = mIn.width, h = mIn.height;
    const bool alongX = side == 0 || side == 2;
    mRefining = side;
    mSides[side].clear();
    for (int32_t e = 0; e < int32_t(mV.size()); ++e)
      if (mOpp[size_t(e)] < 0) addSideEdge(e);
    auto sampleAt = [&](int32_t q) {
      switch (side) {
        case 0:
          return sample(q, 0);
        case 1:
          return sample(w, q);
        case 2:
          return sample(q, h);
        default:
          return sample(0, q);
      }
    };
    std::vector<int32_t> ends;
    for (const auto& [lo, e] : mSides[side]) {
      const Point a = at(e), b = at(next(e));
      ends.push_back(lo);
      ends.push_back(std::max(alongX ? a.x : a.y, alongX ? b.x : b.y));
    }
    std::sort(ends.begin(), ends.end());
    ends.erase(std::unique(ends.begin(), ends.end()), ends.end());
    std::vector<int32_t> added;
    std::vector<std::pair<int32_t, int32_t>> work;
    for (size_t i = 0; i + 1 < ends.size(); ++i) work.emplace_back(ends[i], ends[i + 1]);
    while (!work.empty()) {
      const auto [a, b] = work.back();
      work.pop_back();
      double worst = 0.0;
      int32_t where = -1;
      const size_t sa = sampleAt(a), sb = sampleAt(b);
      for (int32_t q = a + 1; q < b; ++q) {
        const double z =
            lerpOnSegment(mIn.heights[sa], mIn.heights[sb], double(q - a) / double(b - a));
        double v = violation(sampleAt(q), z);
        if (gapHolds())
          v = std::max(v, gapViolation(sampleAt(q),
                                       lerpOnSegment(mIn.parentHeights[sa], mIn.parentHeights[sb],
                                                     double(q - a) / double(b - a))));
        if (v > worst) {
          worst = v;
          where = q;
        }
      }
      if (where < 0) continue;
      added.push_back(where);
      work.emplace_back(a, where);
      work.emplace_back(where, b);
    }
    std::sort(added.begin(), added.end());
    for (const int32_t q : added) {
      const Point p = side == 0   ? Point{q, 0}
                      : side == 1 ? Point{w, q}
                      : side == 2 ? Point{q, h}
                                  : Point{0, q};
      auto it = mSides[side].upper_bound(q);
      assert(it != mSides[side].begin());
      --it;
      splitEdge(it->second, pointIndex(p));
      mTouched.clear();
    }
  }

  // The worst sample off the rectangle's sides (refineSide settled those) in the
  // counter-clockwise triangle (a, b, c): the largest violation above `floor` and where (-1:
  // none above it).
  struct Worst {
    double violation;
    int32_t sample;
  };
  Worst worstSample(int32_t a, int32_t b, int32_t c, double floor) const {
    const double za = height(a), zb = height(b), zc = height(c);
    const bool gap = gapHolds();
    const double pa = gap ? parentAt(a) : 0.0, pb = gap ? parentAt(b) : 0.0,
                 pc = gap ? parentAt(c) : 0.0;
    Worst worst{floor, -1};
    forEachInteriorSample(a, b, c, [&](size_t s, double w0, double w1, double w2, double inv) {
      double v = violation(s, (w0 * za + w1 * zb + w2 * zc) * inv);
      if (gap) v = std::max(v, gapViolation(s, (w0 * pa + w1 * pb + w2 * pc) * inv));
      if (v > worst.violation) worst = {v, int32_t(s)};
      return true;
    });
    return worst;
  }

  // Calls visit(sample, w0, w1, w2, inv) for every sample off the rectangle's sides in the
  // counter-clockwise triangle (a, b, c), with a, b and c's barycentric weights there
  // w0 * inv, w1 * inv and w2 * inv, until it returns false (then false).
  template <typename Visit>
  bool forEachInteriorSample(int32_t a, int32_t b, int32_t c, Visit&& visit) const {
    const int64_t ax = mP[size_t(a)].x, ay = mP[size_t(a)].y, bx = mP[size_t(b)].x,
                  by = mP[size_t(b)].y, cx = mP[size_t(c)].x, cy = mP[size_t(c)].y;
    const int64_t area = orient(ax, ay, bx, by, cx, cy);
    assert(area > 0);
    const double inv = 1.0 / double(area);
    const int64_t d0 = -(cy - by), d1 = -(ay - cy), d2 = -(by - ay);
    bool stopped = false;
    forEachTriangleRow(
        mP[size_t(a)], mP[size_t(b)], mP[size_t(c)], 1, mIn.width - 1, 1, mIn.height - 1,
        [&](int64_t y, int64_t lo, int64_t hi) {
          if (stopped) return;
          int64_t w0 = orient(bx, by, cx, cy, lo, y), w1 = orient(cx, cy, ax, ay, lo, y),
                  w2 = orient(ax, ay, bx, by, lo, y);
          for (int64_t x = lo; x <= hi && !stopped; ++x, w0 += d0, w1 += d1, w2 += d2)
            stopped =
                !visit(sample(int32_t(x), int32_t(y)), double(w0), double(w1), double(w2), inv);
        });
    return !stopped;
  }

  // Scans triangle t for its worst sample and queues it where it breaks the bound.
  void evaluate(int32_t t) {
    const Worst worst =
        worstSample(mV[3 * size_t(t)], mV[3 * size_t(t) + 1], mV[3 * size_t(t) + 2], 0.0);
    mCandidate[size_t(t)] = worst.sample;
    if (worst.sample >= 0) mQueue.push({worst.violation, t, mSerial[size_t(t)]});
  }

  void insertCandidate(int32_t t) {
    const int32_t s = mCandidate[size_t(t)];
    // A vertex's own sample out of the bound cannot be mended by inserting it: that happens only
    // where the parent's surface breaks its own bound at the vertex (an input out of contract),
    // which no mesh of these vertices can hold. Left as it is rather than inserted again.
    if (mPointIndex[size_t(s)] >= 0) return;
    const Point p{int32_t(size_t(s) % mStride), int32_t(size_t(s) / mStride)};
    const int32_t ip = pointIndex(p);
    if (orient(at(3 * t), at(3 * t + 1), p) == 0)
      splitEdge(3 * t, ip);
    else if (orient(at(3 * t + 1), at(3 * t + 2), p) == 0)
      splitEdge(3 * t + 1, ip);
    else if (orient(at(3 * t + 2), at(3 * t), p) == 0)
      splitEdge(3 * t + 2, ip);
    else
      splitTriangle(t, ip);
    std::sort(mTouched.begin(), mTouched.end());
    mTouched.erase(std::unique(mTouched.begin(), mTouched.end()), mTouched.end());
    const std::vector<int32_t> touched = std::move(mTouched);
    mTouched.clear();
    if (!mSeeding)
      for (const int32_t u : touched) evaluate(u);
  }

  // p strictly inside t = (a, b, c): three triangles around p.
  void splitTriangle(int32_t t, int32_t p) {
    const size_t e = 3 * size_t(t);
    const int32_t a = mV[e], b = mV[e + 1], c = mV[e + 2];
    const int32_t oab = mOpp[e], obc = mOpp[e + 1], oca = mOpp[e + 2];
    const uint8_t fab = mFixed[e], fbc = mFixed[e + 1], fca = mFixed[e + 2];
    setTriangle(t, a, b, p);
    const int32_t t1 = addTriangle(b, c, p), t2 = addTriangle(c, a, p);
    link(3 * t, oab, fab);
    link(3 * t + 1, 3 * t1 + 2, 0);
    link(3 * t + 2, 3 * t2 + 1, 0);
    link(3 * t1, obc, fbc);
    link(3 * t1 + 1, 3 * t2 + 2, 0);
    link(3 * t2, oca, fca);
    legalize(3 * t);
    legalize(3 * t1);
    legalize(3 * t2);
  }

  // p on the edge e = (a -> b) of T = (a, b, c), strictly between a and b: two triangles, or
  // four with the triangle across. The halves keep the edge's fixedness.
  void splitEdge(int32_t e, int32_t p) {
    const int32_t T = e / 3;
    const int32_t a = mV[size_t(e)], b = mV[size_t(next(e))], c = mV[size_t(prev(e))];
    const int32_t xbc = mOpp[size_t(next(e))], xca = mOpp[size_t(prev(e))];
    const uint8_t fbc = mFixed[size_t(next(e))], fca = mFixed[size_t(prev(e))];
    const uint8_t fixed = mFixed[size_t(e)];
    const int32_t f = mOpp[size_t(e)];
    if (f < 0) {
      setTriangle(T, c, a, p);
      const int32_t T1 = addTriangle(c, p, b);
      link(3 * T, xca, fca);
      link(3 * T + 1, -1, kLine);
      link(3 * T + 2, 3 * T1, 0);
      link(3 * T1 + 1, -1, kLine);
      link(3 * T1 + 2, xbc, fbc);
      addSideEdge(3 * T + 1);
      addSideEdge(3 * T1 + 1);
      legalize(3 * T);
      legalize(3 * T1 + 2);
      return;
    }
    const int32_t U = f / 3;
    const int32_t d = mV[size_t(prev(f))];
    const int32_t ydb = mOpp[size_t(prev(f))], yad = mOpp[size_t(next(f))];
    const uint8_t fdb = mFixed[size_t(prev(f))], fad = mFixed[size_t(next(f))];
    setTriangle(T, c, a, p);
    setTriangle(U, d, b, p);
    const int32_t T1 = addTriangle(c, p, b), U1 = addTriangle(d, p, a);
    link(3 * T, xca, fca);
    link(3 * T + 1, 3 * U1 + 1, fixed);
    link(3 * T + 2, 3 * T1, 0);
    link(3 * T1 + 1, 3 * U + 1, fixed);
    link(3 * T1 + 2, xbc, fbc);
    link(3 * U, ydb, fdb);
    link(3 * U + 2, 3 * U1, 0);
    link(3 * U1 + 2, yad, fad);
    legalize(3 * T);
    legalize(3 * T1 + 2);
    legalize(3 * U);
    legalize(3 * U1 + 2);
  }

  // e = (a -> b) in T = (a, b, p) with p the point just inserted: flips e, unless it is fixed,
  // while the vertex across it lies inside T's circumcircle.
  void legalize(int32_t e) {
    const int32_t f = mOpp[size_t(e)];
    if (f < 0 || mFixed[size_t(e)] == kLine) return;
    const int32_t T = e / 3, U = f / 3;
    const int32_t a = mV[size_t(e)], b = mV[size_t(next(e))], p = mV[size_t(prev(e))];
    const int32_t q = mV[size_t(prev(f))];
    if (!inCircle(mP[size_t(a)], mP[size_t(b)], mP[size_t(p)], mP[size_t(q)])) return;
    if (mFixed[size_t(e)] == kParentEdge && !(morphs() && withinGap(p, a, q) && withinGap(q, b, p)))
      return;
    flip(e);
    legalize(3 * T + 1);
    legalize(3 * U);
  }

  // Whether the triangle (a, b, c) with its corners on the parent's surface stays within the
  // gap of it at every sample (counter-clockwise; flat: no).
  bool withinGap(int32_t a, int32_t b, int32_t c) const {
    const SurfaceCorner corners[3] = {{mP[size_t(a)].x, mP[size_t(a)].y, parentAt(a)},
                                      {mP[size_t(b)].x, mP[size_t(b)].y, parentAt(b)},
                                      {mP[size_t(c)].x, mP[size_t(c)].y, parentAt(c)}};
    if (orient(mP[size_t(a)], mP[size_t(b)], mP[size_t(c)]) <= 0) return false;
    bool ok = true;
    rasterizeTriangle(corners, 0, 0, mIn.width, mIn.height, [&](int32_t x, int32_t y, double z) {
      ok = ok && gapViolation(sample(x, y), z) <= kGapSlack;
    });
    return ok;
  }
  static constexpr double kGapSlack = 1e-9;  ///< rounding, where the gap is 0 (coplanar)

  // Greedy insertion adds each vertex against the mesh as it stood; once every sample is
  // within the bound, some vertices are no longer needed. A vertex whose edges are all free
  // (not on a side, a line or a parent's edge) is collapsed onto the neighbour that leaves its
  // star with the smallest violation, if every sample there stays within the bound (and, while
  // morphing, the gap): the same test evaluate() makes. Vertices are tried in index order, and
  // again only once a collapse has changed the triangles around them, until none goes.
  // Collapsed triangles are marked dead (-1).
  void simplify() {
    mOut.assign(mP.size(), -1);
    for (int32_t e = 0; e < int32_t(mV.size()); ++e)
      if (mV[size_t(e)] >= 0) mOut[size_t(mV[size_t(e)])] = e;
    mDirty.assign(mP.size(), 1);
    for (bool removed = true; removed;) {
      removed = false;
      for (int32_t v = 0; v < int32_t(mP.size()); ++v) {
        if (!mDirty[size_t(v)]) continue;
        mDirty[size_t(v)] = 0;
        removed = collapse(v) || removed;
      }
    }
  }

  // v's outgoing half-edges counter-clockwise from mOut[v]; false where v is on the
  // rectangle's sides or on a fixed edge (a line's or a parent's). Letting a vertex on a line or
  // a parent edge go along it as well was tried: 0.1 % fewer triangles, not kept.
  bool starOf(int32_t v, std::vector<int32_t>& out) const {
    out.clear();
    if (mOut[size_t(v)] < 0 || !forEachOutgoing(v, [&](int32_t e) { out.push_back(e); }))
      return false;
    for (const int32_t e : out)
      if (mFixed[size_t(e)] != kFree) return false;
    return out.size() >= 3;
  }

  // The largest violation over the interior samples of triangle (a, b, c), as evaluate()
  // measures it (<= 0: within the bound and the gap); +inf when it is not counter-clockwise.
  double triangleViolation(int32_t a, int32_t b, int32_t c) const {
    if (orient(mP[size_t(a)], mP[size_t(b)], mP[size_t(c)]) <= 0)
      return std::numeric_limits<double>::infinity();
    return worstSample(a, b, c, -std::numeric_limits<double>::infinity()).violation;
  }

  bool collapse(int32_t v) {
    std::vector<int32_t>& star = mStar;
    if (!starOf(v, star)) return false;
    // Neighbours: the far end of each outgoing edge. u must share no neighbour with v but the
    // two corners beside their edge (else the collapse would join two edges into one).
    int32_t best = -1;
    Placement bestPlace{0.0, 0.0};
    for (size_t i = 0; i < star.size(); ++i) {
      const int32_t u = mV[size_t(next(star[i]))];
      const Placement place = placeOnto(v, u, star);
      if (place.violation > 0.0 || !linkHolds(u, star)) continue;
      if (best < 0 || place.violation < bestPlace.violation) best = int32_t(i), bestPlace = place;
    }
    if (best < 0) return false;
    const int32_t e0 = star[size_t(best)];  // v -> u in T1 = (v, u, x)
    const int32_t u = mV[size_t(next(e0))];
    const int32_t f0 = mOpp[size_t(e0)];  // u -> v in T2 = (u, v, y)
    // T1's and T2's outer edges become twins of each other.
    const int32_t e1 = next(e0), e2 = prev(e0), f1 = next(f0), f2 = prev(f0);
    const int32_t o1 = mOpp[size_t(e1)], o2 = mOpp[size_t(e2)];
    const int32_t p1 = mOpp[size_t(f1)], p2 = mOpp[size_t(f2)];
    const uint8_t k1 = std::max(mFixed[size_t(e1)], mFixed[size_t(e2)]);
    const uint8_t k2 = std::max(mFixed[size_t(f1)], mFixed[size_t(f2)]);
    const int32_t t1 = e0 / 3, t2 = f0 / 3;
    for (const int32_t e : star) {
      const int32_t t = e / 3;
      if (t == t1 || t == t2) continue;
      mV[size_t(e)] = u;
    }
    for (const int32_t t : {t1, t2})
      for (int i = 0; i < 3; ++i) {
        mV[3 * size_t(t) + size_t(i)] = -1;
        mOpp[3 * size_t(t) + size_t(i)] = -1;
      }
    // o2 and p1 are twins of v's free edges (starOf), so they exist; o1 and p2 may be sides.
    link(o2, o1, k1);
    link(p1, p2, k2);
    mOut[size_t(v)] = -1;
    for (const int32_t e : star) {
      const int32_t t = e / 3;
      if (t == t1 || t == t2) continue;
      for (int i = 0; i < 3; ++i) {
        const auto w = size_t(mV[3 * size_t(t) + size_t(i)]);
        mOut[w] = 3 * t + i;
        mDirty[w] = 1;
      }
    }
    if (bestPlace.z != mZ[size_t(u)]) {
      mZ[size_t(u)] = bestPlace.z;
      forEachOutgoing(u, [&](int32_t e) { mDirty[size_t(mV[size_t(next(e))])] = 1; });
    }
    return true;
  }

  // Whether a vertex's height may move off its sample: not on the rectangle's sides, whose
  // vertices neighbours choose alike from the heights along them.
  bool heightFree(int32_t u) const {
    if (mIn.vertexHeights != VertexHeights::kFitted) return false;
    const Point p = mP[size_t(u)];
    return p.x > 0 && p.y > 0 && p.x < mIn.width && p.y < mIn.height;
  }

  // Collapsing v onto u: the height u takes and the largest violation over the samples of the
  // triangles that change (> 0: the collapse is refused). A vertex on a side keeps its height
  // and only v's star changes; any other takes the middle of the heights that keep every sample
  // of its whole new star (its own triangles but the two that vanish, and v's others now
  // joined to it) within the bound: a vertex need not be at its sample's height, only the
  // surface within the bound of every sample, and that freedom lets more collapses go.
  struct Placement {
    double violation;
    double z;
  };
  Placement placeOnto(int32_t v, int32_t u, const std::vector<int32_t>& star) {
    const double refused = std::numeric_limits<double>::infinity();
    if (!heightFree(u)) {
      double worst = -std::numeric_limits<double>::infinity();
      for (size_t j = 0; j < star.size() && worst <= 0.0; ++j) {
        // Triangle j is (v, w1, w2); it vanishes where it holds u.
        const int32_t w1 = mV[size_t(next(star[j]))], w2 = mV[size_t(prev(star[j]))];
        if (w1 == u || w2 == u) continue;
        worst = std::max(worst, triangleViolation(u, w1, w2));
      }
      return {worst, mZ[size_t(u)]};
    }
    // Every sample's surface is wu * z + rest; |wu * z + rest - h| <= error bounds z where
    // wu > 0.
    double fixedWorst = -std::numeric_limits<double>::infinity();
    double lo = -std::numeric_limits<double>::infinity(),
           hi = std::numeric_limits<double>::infinity();
    std::vector<Constraint>& cons = mConstraints;
    cons.clear();
    const bool gap = gapHolds();
    // Whether z can still be placed.
    auto constrain = [&](size_t s, double wu, double rest) {
      if (wu <= 0.0) {
        fixedWorst = std::max(fixedWorst, violation(s, rest));
      } else {
        tighten(lo, hi, s, wu, rest);
        cons.push_back({s, wu, rest});
      }
      return fixedWorst <= 0.0 && lo <= hi;
    };
    for (const int32_t e : star) {
      const int32_t w1 = mV[size_t(next(e))], w2 = mV[size_t(prev(e))];
      if (w1 == u || w2 == u) continue;
      if (orient(mP[size_t(u)], mP[size_t(w1)], mP[size_t(w2)]) <= 0) return {refused, 0.0};
      const double z1 = mZ[size_t(w1)], z2 = mZ[size_t(w2)];
      const double pu = gap ? parentAt(u) : 0.0, p1 = gap ? parentAt(w1) : 0.0,
                   p2 = gap ? parentAt(w2) : 0.0;
      const bool ok = forEachInteriorSample(
          u, w1, w2, [&](size_t s, double a0, double a1, double a2, double inv) {
            if (gap)
              fixedWorst =
                  std::max(fixedWorst, gapViolation(s, (a0 * pu + a1 * p1 + a2 * p2) * inv));
            return constrain(s, a0 * inv, (a1 * z1 + a2 * z2) * inv);
          });
      if (!ok) return {refused, 0.0};
    }
    // And u's own triangles, but the two that vanish.
    if (!forEachStarSample(u, v, constrain)) return {refused, 0.0};
    const double z = cons.empty() ? mZ[size_t(u)] : 0.5 * (lo + hi);
    double worst = fixedWorst;
    for (const Constraint& c : cons)
      worst = std::max(worst, violation(c.sample, c.wu * z + c.rest));
    return {worst, z};
  }
  struct Constraint {
    size_t sample;
    double wu, rest;
  };

  // Narrows [lo, hi], the heights a vertex may take, by sample s, whose surface is wu * z + rest
  // (wu > 0). Divides only where the bound tightens (rarely, after the first samples).
  void tighten(double& lo, double& hi, size_t s, double wu, double rest) const {
    const double below = mIn.heights[s] - mIn.error - rest,
                 above = mIn.heights[s] + mIn.error - rest;
    if (!(below <= lo * wu)) lo = below / wu;
    if (!(above >= hi * wu)) hi = above / wu;
  }

  // Moves every vertex off the sides to the middle of the heights its triangles allow. Each
  // collapse left the vertex it kept in the middle for its star then; the collapses around it
  // since have moved the surface, so a vertex may sit near one end, leaving its neighbours no
  // room. A second round of collapses after this removes 1.5-3 % more triangles for a fifth
  // more time (each further round about 1 %, for half the time again).
  void recentre() {
    for (int32_t u = 0; u < int32_t(mP.size()); ++u) {
      if (mOut[size_t(u)] < 0 || !heightFree(u)) continue;
      double lo = -std::numeric_limits<double>::infinity(),
             hi = std::numeric_limits<double>::infinity();
      const bool closed = forEachStarSample(u, -1, [&](size_t s, double wu, double rest) {
        if (wu > 0.0) tighten(lo, hi, s, wu, rest);
        return true;
      });
      if (closed && lo <= hi && std::isfinite(lo) && std::isfinite(hi))
        mZ[size_t(u)] = 0.5 * (lo + hi);
    }
  }

  // Calls visit(s, wu, rest) for every sample off the rectangle's sides in u's triangles but
  // those holding vertex `skip`, where the surface is wu * z + rest in u's height z, until it
  // returns false; false then, or where u's star does not close.
  template <typename Visit>
  bool forEachStarSample(int32_t u, int32_t skip, Visit&& visit) const {
    bool going = true;
    const bool closed = forEachOutgoing(u, [&](int32_t e) {
      const int32_t b = mV[size_t(next(e))], c = mV[size_t(prev(e))];
      if (!going || b == skip || c == skip) return;
      const double zb = mZ[size_t(b)], zc = mZ[size_t(c)];
      going = forEachInteriorSample(u, b, c,
                                    [&](size_t s, double a0, double a1, double a2, double inv) {
                                      return visit(s, a0 * inv, (a1 * zb + a2 * zc) * inv);
                                    });
    });
    return going && closed;
  }

  // Calls f(e) for each outgoing half-edge of vertex u counter-clockwise (one per triangle
  // around it); false where the walk did not close (u on a side, or past kMaxDegree).
  template <typename F>
  bool forEachOutgoing(int32_t u, F&& f) const {
    return walkOutgoing(mOut[size_t(u)], f);
  }
  // The same from half-edge `first`.
  template <typename F>
  bool walkOutgoing(int32_t first, F&& f) const {
    int32_t e = first;
    for (int steps = 0; steps < kMaxDegree; ++steps) {
      f(e);
      e = mOpp[size_t(prev(e))];
      if (e < 0) return false;
      if (e == first) return true;
    }
    return false;
  }

  // The link condition: the vertices next to both v (its outgoing edges `star`) and u are
  // exactly the two beside edge v-u. False also where u's neighbours cannot all be found.
  bool linkHolds(int32_t u, const std::vector<int32_t>& star) {
    // u's neighbours, walking its star both ways from mOut[u] (u may be on a side or a line,
    // where a walk stops at the boundary).
    std::vector<int32_t>& seen = mSeen;
    seen.clear();
    const int32_t first = mOut[size_t(u)];
    bool closed = false;
    for (int dir = 0; dir < 2 && !closed; ++dir) {
      int32_t e = first;
      for (int steps = 0;; ++steps) {
        if (steps == kMaxDegree) return false;
        seen.push_back(mV[size_t(next(e))]);
        seen.push_back(mV[size_t(prev(e))]);
        const int32_t opp = dir == 0 ? mOpp[size_t(prev(e))] : mOpp[size_t(e)];
        if (opp < 0) break;
        e = dir == 0 ? opp : next(opp);
        if (e == first) {
          closed = true;
          break;
        }
      }
    }
    std::sort(seen.begin(), seen.end());
    seen.erase(std::unique(seen.begin(), seen.end()), seen.end());
    int shared = 0;
    for (const int32_t e : star) {
      const int32_t w = mV[size_t(next(e))];
      if (w != u && std::binary_search(seen.begin(), seen.end(), w)) ++shared;
    }
    return shared == 2;
  }
  static constexpr int kMaxDegree = 256;  ///< a star walk longer than this gives up

  // The triangles in meshoptimizer's strip order (each triangle mostly sharing an edge with
  // the last, as RTIN's Sierpinski order does) and the vertices in the order they are first
  // used: what the index and vertex codecs compress best (insertion order compresses ~5x
  // worse in the index codec; the vertex-cache order ~1.5x).
  GreedyMesh ordered() const {
    std::vector<uint32_t> inserted;
    inserted.reserve(mV.size());
    for (const int32_t v : mV)
      if (v >= 0) inserted.push_back(uint32_t(v));
    GreedyMesh out;
    out.triangles.resize(inserted.size());
    meshopt_optimizeVertexCacheStrip(out.triangles.data(), inserted.data(), inserted.size(),
                                     mP.size());
    std::vector<uint32_t> remap(mP.size());
    const size_t used = meshopt_optimizeVertexFetchRemap(remap.data(), out.triangles.data(),
                                                         out.triangles.size(), mP.size());
    out.x.resize(used);
    out.y.resize(used);
    out.z.resize(used);
    for (size_t i = 0; i < mP.size(); ++i) {
      if (remap[i] == ~0u) continue;
      out.x[remap[i]] = mP[i].x;
      out.y[remap[i]] = mP[i].y;
      out.z[remap[i]] = mZ[i];
    }
    for (uint32_t& v : out.triangles) v = remap[v];
    return out;
  }

  const GreedyMeshInput& mIn;
  const size_t mStride;
  std::vector<Point> mP;
  std::vector<double> mZ;  ///< per vertex: its height (the sample's until a collapse moves it)
  std::vector<int32_t> mPointIndex;  ///< per sample: its vertex, or -1
  std::vector<int32_t> mV, mOpp, mCandidate;
  std::vector<uint8_t> mFixed;
  std::vector<uint32_t> mSerial;
  std::vector<int32_t> mTouched;
  std::vector<int32_t> mOut;    ///< per vertex: one outgoing half-edge (simplify)
  std::vector<uint8_t> mDirty;  ///< per vertex: its star changed since it was last tried
  std::vector<int32_t> mStar;
  std::vector<Constraint> mConstraints;
  std::vector<int32_t> mSeen;
  std::map<int32_t, int32_t> mSides[4];
  std::priority_queue<Entry> mQueue;
  int mRefining = -1;  ///< the side refineSide works on (mSides[side] kept up to date)
  bool mDegenerate = false;
  bool mSeeding = false;           ///< inserting the parent's vertices: nothing evaluated yet
  std::vector<int32_t> mIncident;  ///< seedFromVertices: per vertex, a half-edge out of it
};

}  // namespace

GreedyMesh greedyMesh(const GreedyMeshInput& input) {
  assert(input.width > 0 && input.height > 0);
  assert(input.heights.size() == size_t(input.width + 1) * (input.height + 1));
  GreedyMesh out;
  if (!Mesher(input).run(out)) return {};
  return out;
}

double greedyMeshViolation(const GreedyMeshInput& input, const GreedyMesh& mesh) {
  const size_t stride = size_t(input.width) + 1;
  std::vector<double> own(input.heights.size(), std::nan(""));
  for (size_t k = 0; k + 2 < mesh.triangles.size(); k += 3) {
    SurfaceCorner corners[3];
    for (int i = 0; i < 3; ++i) {
      const uint32_t v = mesh.triangles[k + size_t(i)];
      corners[i] = {mesh.x[v], mesh.y[v], mesh.z[v]};
    }
    rasterizeTriangle(corners, 0, 0, input.width, input.height,
                      [&](int32_t x, int32_t y, double z) { own[size_t(y) * stride + x] = z; });
  }
  double worst = -std::numeric_limits<double>::infinity();
  for (size_t s = 0; s < own.size(); ++s) {
    if (std::isnan(own[s])) return std::numeric_limits<double>::infinity();  // a hole
    worst = std::max(worst, std::fabs(own[s] - input.heights[s]) - input.error);
  }
  return worst;
}

}  // namespace terralod
