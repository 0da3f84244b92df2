#include "patch_mesh.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstddef>

namespace terralod {
namespace {

struct Point {
  int64_t x, y;
};

// Twice the signed area of (a, b, c): positive when counter-clockwise.
int64_t area2(Point a, Point b, Point c) {
  return (b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y);
}

int64_t floorDiv(int64_t a, int64_t b) {
  const int64_t q = a / b;
  return (a % b != 0 && ((a < 0) != (b < 0))) ? q - 1 : q;
}
int64_t ceilDiv(int64_t a, int64_t b) {
  return -floorDiv(-a, b);
}

enum Side { kWest = 1, kEast = 2, kSouth = 4, kNorth = 8, kSeamX = 16, kSeamY = 32 };

}  // namespace

double triangleError(const GridPatch& patch, uint16_t ia, uint16_t ib, uint16_t ic, double limit) {
  const Point a{patch.xOf(ia), patch.yOf(ia)};
  const Point b{patch.xOf(ib), patch.yOf(ib)};
  const Point c{patch.xOf(ic), patch.yOf(ic)};
  const int64_t det = area2(a, b, c);
  assert(det > 0);
  const double za = patch.vertexHeight(ia), zb = patch.vertexHeight(ib),
               zc = patch.vertexHeight(ic);
  const double gx = ((zb - za) * double(c.y - a.y) - double(b.y - a.y) * (zc - za)) / double(det);
  const double gy = (double(b.x - a.x) * (zc - za) - (zb - za) * double(c.x - a.x)) / double(det);
  const Point corners[3] = {a, b, c};
  const int64_t y0 = std::min({a.y, b.y, c.y}), y1 = std::max({a.y, b.y, c.y});
  const int64_t bx0 = std::min({a.x, b.x, c.x}), bx1 = std::max({a.x, b.x, c.x});
  double worst = 0.0;
  for (int64_t y = y0; y <= y1; ++y) {
    // Each counter-clockwise edge p -> q keeps the points with cross(q - p, s - p) >= 0,
    // which for this row is C - D x >= 0.
    int64_t lo = bx0, hi = bx1;
    for (int e = 0; e < 3; ++e) {
      const Point p = corners[e], q = corners[(e + 1) % 3];
      const int64_t d = q.y - p.y;
      const int64_t cst = (q.x - p.x) * (y - p.y) + d * p.x;
      if (d > 0) {
        hi = std::min(hi, floorDiv(cst, d));
      } else if (d < 0) {
        lo = std::max(lo, ceilDiv(cst, d));
      } else if (cst < 0) {
        lo = hi + 1;
      }
    }
    const float* row = patch.heights.data() + size_t(y) * size_t(patch.width);
    const double rowBase = za + gy * double(y - a.y) - gx * double(a.x);
    for (int64_t x = lo; x <= hi; ++x) {
      const double d = std::abs(double(row[x]) - (rowBase + gx * double(x)));
      if (d > worst) {
        worst = d;
        if (worst > limit) return worst;
      }
    }
  }
  return worst;
}

PatchMesh::PatchMesh(const GridPatch& patch, MaterialRules rules,
                     std::vector<std::array<uint16_t, 3>> triangles, int32_t seamX, int32_t seamY)
    : mPatch(patch), mRules(rules), mSeamX(seamX), mSeamY(seamY), mTriangles(std::move(triangles)) {
  mIncident.resize(patch.pointCount());
  mMark.assign(patch.pointCount(), 0);
  mMark2.assign(patch.pointCount(), 0);
  mErrors.reserve(size_t(patch.pointCount()) * 16);
  for (uint32_t t = 0; t < mTriangles.size(); ++t)
    for (uint16_t v : mTriangles[t]) mIncident[v].push_back(t);
}

int PatchMesh::sides(uint16_t v) const {
  const int32_t x = mPatch.xOf(v), y = mPatch.yOf(v);
  return (x == 0 ? kWest : 0) | (x == mPatch.width - 1 ? kEast : 0) | (y == 0 ? kSouth : 0) |
         (y == mPatch.height - 1 ? kNorth : 0) | (x == mSeamX ? kSeamX : 0) |
         (y == mSeamY ? kSeamY : 0);
}

void PatchMesh::neighbours(uint16_t v, std::vector<uint16_t>& out) const {
  const uint32_t stamp = ++mStamp;
  mMark[v] = stamp;
  for (uint32_t t : mIncident[v])
    for (uint16_t w : mTriangles[t])
      if (mMark[w] != stamp) {
        mMark[w] = stamp;
        out.push_back(w);
      }
}

bool PatchMesh::onMaterialBoundary(uint16_t v) const {
  const uint8_t m = mPatch.materials[v];
  for (uint32_t t : mIncident[v])
    for (uint16_t w : mTriangles[t])
      if (mPatch.materials[w] != m) return true;
  return false;
}

// Rule 3: after v -> u, the triangle covering v's position has only corners of v's material
// among those with a non-zero weight there.
bool PatchMesh::materialStays(uint16_t v, uint16_t u) const {
  const uint8_t m = mPatch.materials[v];
  const Point p{mPatch.xOf(v), mPatch.yOf(v)};
  bool covered = false;
  for (uint32_t t : mIncident[v]) {
    std::array<uint16_t, 3> tri = mTriangles[t];
    if (std::find(tri.begin(), tri.end(), u) != tri.end()) continue;
    for (uint16_t& w : tri)
      if (w == v) w = u;
    const Point c[3] = {{mPatch.xOf(tri[0]), mPatch.yOf(tri[0])},
                        {mPatch.xOf(tri[1]), mPatch.yOf(tri[1])},
                        {mPatch.xOf(tri[2]), mPatch.yOf(tri[2])}};
    // Weight of corner i is proportional to the area of the triangle opposite it.
    const int64_t w0 = area2(p, c[1], c[2]), w1 = area2(c[0], p, c[2]), w2 = area2(c[0], c[1], p);
    if (w0 < 0 || w1 < 0 || w2 < 0) continue;
    covered = true;
    const int64_t weights[3] = {w0, w1, w2};
    for (int i = 0; i < 3; ++i)
      if (weights[i] > 0 && mPatch.materials[tri[i]] != m) return false;
  }
  return covered;
}

double PatchMesh::collapseError(uint16_t v, uint16_t u, double limit) const {
  constexpr double kNo = std::numeric_limits<double>::infinity();
  const int sv = sides(v);
  if (sv != 0) {
    if ((sv & (sv - 1)) != 0) return kNo;  // a corner
    if ((sides(u) & sv) == 0) return kNo;  // off its side
  }
  const bool rules = mRules == MaterialRules::kOn;
  if (rules && mPatch.materials[v] != mPatch.materials[u]) return kNo;
  // The triangles on edge vu die (one on a side, two inside); no other may turn over or
  // degenerate seen from above.
  int dying = 0;
  const Point pu{mPatch.xOf(u), mPatch.yOf(u)};
  for (uint32_t t : mIncident[v]) {
    const auto& tri = mTriangles[t];
    if (tri[0] == u || tri[1] == u || tri[2] == u) {
      ++dying;
      continue;
    }
    Point c[3];
    for (int i = 0; i < 3; ++i)
      c[i] = tri[i] == v ? pu : Point{mPatch.xOf(tri[i]), mPatch.yOf(tri[i])};
    if (area2(c[0], c[1], c[2]) <= 0) return kNo;
  }
  if (dying == 0 || dying > 2) return kNo;
  // Link condition: v and u share exactly the neighbours opposite their edge.
  const uint32_t uStamp = ++mStamp;
  for (uint32_t t : mIncident[u])
    for (uint16_t w : mTriangles[t]) mMark[w] = uStamp;
  const uint32_t vStamp = ++mStamp;
  int shared = 0;
  mMark2[v] = vStamp;
  mMark2[u] = vStamp;
  for (uint32_t t : mIncident[v])
    for (uint16_t w : mTriangles[t])
      if (mMark2[w] != vStamp) {
        mMark2[w] = vStamp;
        if (mMark[w] == uStamp) ++shared;
      }
  if (shared != dying) return kNo;
  if (rules) {
    if (onMaterialBoundary(v) && !onMaterialBoundary(u)) return kNo;
    if (!materialStays(v, u)) return kNo;
  }
  double worst = 0.0;
  for (uint32_t t : mIncident[v]) {
    std::array<uint16_t, 3> tri = mTriangles[t];
    if (tri[0] == u || tri[1] == u || tri[2] == u) continue;
    for (uint16_t& w : tri)
      if (w == v) w = u;
    worst = std::max(worst, cachedTriangleError(tri[0], tri[1], tri[2], limit));
    if (worst > limit) return kNo;
  }
  return worst;
}

double PatchMesh::cachedTriangleError(uint16_t a, uint16_t b, uint16_t c, double limit) const {
  // The same triangle in any rotation (orientation is always counter-clockwise).
  while (a > b || a > c) {
    const uint16_t t = a;
    a = b;
    b = c;
    c = t;
  }
  const uint64_t key = (uint64_t(a) << 32) | (uint64_t(b) << 16) | c;
  auto [it, fresh] = mErrors.try_emplace(key, KnownError{0.0, false});
  KnownError& known = it->second;
  if (!fresh && (known.exact || known.error > limit)) return known.error;
  known.error = triangleError(mPatch, a, b, c, limit);
  known.exact = known.error <= limit;
  return known.error;
}

void PatchMesh::collapse(uint16_t v, uint16_t u) {
  std::vector<uint32_t> moved = std::move(mIncident[v]);
  mIncident[v].clear();
  for (uint32_t t : moved) {
    auto& tri = mTriangles[t];
    if (std::find(tri.begin(), tri.end(), u) != tri.end()) {
      for (uint16_t w : tri) {
        if (w == v) continue;
        auto& list = mIncident[w];
        list.erase(std::find(list.begin(), list.end(), t));
      }
      continue;
    }
    for (uint16_t& w : tri)
      if (w == v) w = u;
    mIncident[u].push_back(t);
  }
}

std::vector<std::array<uint16_t, 3>> PatchMesh::aliveTriangles() const {
  std::vector<uint8_t> alive(mTriangles.size(), 0);
  for (const auto& list : mIncident)
    for (uint32_t t : list) alive[t] = 1;
  std::vector<std::array<uint16_t, 3>> out;
  for (uint32_t t = 0; t < mTriangles.size(); ++t)
    if (alive[t]) out.push_back(mTriangles[t]);
  return out;
}

}  // namespace terralod
