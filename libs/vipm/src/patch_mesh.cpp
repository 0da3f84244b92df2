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

// Which grid points of a row Plane::row gives: exactly those inside the triangle, or a range
// that holds them, never empty within the triangle's rows (its real extent rounded outward).
enum class RowRange : uint8_t { kInside, kOutward };

// A triangle of a patch (counter-clockwise, positive area) and its plane.
struct Plane {
  Point corners[3];
  double za, gx, gy;
  int64_t y0, y1, x0, x1;  // bounding box

  Plane(const GridPatch& patch, uint16_t ia, uint16_t ib, uint16_t ic) {
    const Point a{patch.xOf(ia), patch.yOf(ia)};
    const Point b{patch.xOf(ib), patch.yOf(ib)};
    const Point c{patch.xOf(ic), patch.yOf(ic)};
    corners[0] = a;
    corners[1] = b;
    corners[2] = c;
    const int64_t det = area2(a, b, c);
    assert(det > 0);
    za = patch.vertexHeight(ia);
    const double zb = patch.vertexHeight(ib), zc = patch.vertexHeight(ic);
    gx = ((zb - za) * double(c.y - a.y) - double(b.y - a.y) * (zc - za)) / double(det);
    gy = (double(b.x - a.x) * (zc - za) - (zb - za) * double(c.x - a.x)) / double(det);
    y0 = std::min({a.y, b.y, c.y});
    y1 = std::max({a.y, b.y, c.y});
    x0 = std::min({a.x, b.x, c.x});
    x1 = std::max({a.x, b.x, c.x});
  }
  // The plane's height along row y, as a + b x.
  double rowBase(int64_t y) const {
    return za + gy * double(y - corners[0].y) - gx * double(corners[0].x);
  }
  double at(int64_t x, int64_t y) const { return rowBase(y) + gx * double(x); }
  // The grid points of row y in the closed triangle, [lo, hi] (empty when lo > hi), as `range`
  // says.
  void row(int64_t y, int64_t& lo, int64_t& hi, RowRange range = RowRange::kInside) const {
    const bool inside = range == RowRange::kInside;
    // Each counter-clockwise edge p -> q keeps the points with cross(q - p, s - p) >= 0,
    // which for this row is C - D x >= 0.
    lo = x0;
    hi = x1;
    for (int e = 0; e < 3; ++e) {
      const Point p = corners[e], q = corners[(e + 1) % 3];
      const int64_t d = q.y - p.y;
      const int64_t cst = (q.x - p.x) * (y - p.y) + d * p.x;
      if (d > 0) {
        hi = std::min(hi, inside ? floorDiv(cst, d) : ceilDiv(cst, d));
      } else if (d < 0) {
        lo = std::max(lo, inside ? ceilDiv(cst, d) : floorDiv(cst, d));
      } else if (cst < 0) {
        lo = hi + 1;
      }
    }
  }
};

// Dense patches: the largest distance over the samples inside.
double scannedError(const GridPatch& patch, const Plane& t, double limit) {
  double worst = 0.0;
  for (int64_t y = t.y0; y <= t.y1; ++y) {
    int64_t lo, hi;
    t.row(y, lo, hi);
    const float* row = patch.heights.data() + size_t(y) * size_t(patch.width);
    const double rowBase = t.rowBase(y);
    for (int64_t x = lo; x <= hi; ++x) {
      const double d = std::abs(double(row[x]) - (rowBase + t.gx * double(x)));
      if (d > worst) {
        worst = d;
        if (worst > limit) return worst;
      }
    }
  }
  return worst;
}

// The convex polygon of triangle t clipped to the rectangle [xa, xb] x [ya, yb] (grown by a
// hair, so that it holds every grid point of both despite rounding), into `out`.
void clipToRectangle(const Plane& t, double xa, double xb, double ya, double yb,
                     std::vector<std::array<double, 2>>& out,
                     std::vector<std::array<double, 2>>& scratch) {
  constexpr double kHair = 1e-7;
  out.clear();
  for (const Point& c : t.corners) out.push_back({double(c.x), double(c.y)});
  // Keep the side of each line where coordinate `axis` * sign >= bound * sign.
  auto clip = [&](int axis, double bound, double sign) {
    scratch.clear();
    for (size_t k = 0; k < out.size(); ++k) {
      const auto& p = out[k];
      const auto& q = out[(k + 1) % out.size()];
      const bool pin = (p[size_t(axis)] - bound) * sign >= 0,
                 qin = (q[size_t(axis)] - bound) * sign >= 0;
      if (pin) scratch.push_back(p);
      if (pin != qin) {
        const double f = (bound - p[size_t(axis)]) / (q[size_t(axis)] - p[size_t(axis)]);
        std::array<double, 2> m{p[0] + f * (q[0] - p[0]), p[1] + f * (q[1] - p[1])};
        m[size_t(axis)] = bound;
        scratch.push_back(m);
      }
    }
    out.swap(scratch);
  };
  clip(0, xa - kHair, 1.0);
  if (!out.empty()) clip(0, xb + kHair, -1.0);
  if (!out.empty()) clip(1, ya - kHair, 1.0);
  if (!out.empty()) clip(1, yb + kHair, -1.0);
}

// Sparse patches: a bound over the sample blocks the triangle reaches. Each block's samples
// are its plane plus a residual in [lo, hi]; those inside the triangle lie in the triangle
// clipped to the block's rectangle, over which the block's plane above the triangle's is
// extreme at the corners. Single-sample blocks are measured exactly.
double blockError(const GridPatch& patch, const Plane& t, double limit) {
  const SampleBlocks& s = patch.samples;
  const int64_t step = s.step;
  auto last = [step](int64_t block, int32_t points) {
    return std::min<int64_t>(points - 1, block * step + step - 1);
  };
  thread_local std::vector<std::array<double, 2>> polygon, scratch;
  double worst = 0.0;
  for (int64_t j = t.y0 / step; j * step <= t.y1; ++j) {
    const int64_t ya = std::max(t.y0, j * step), yb = std::min(t.y1, j * step + step - 1);
    int64_t lo, hi;
    if (ya == yb) {
      t.row(ya, lo, hi);
    } else {
      // The triangle's left and right edges are convex and concave in y, bent at its corners
      // (grid rows): their extremes over [ya, yb] are at its ends or at a corner's row.
      int64_t l, h;
      t.row(ya, lo, hi, RowRange::kOutward);
      t.row(yb, l, h, RowRange::kOutward);
      lo = std::min(lo, l);
      hi = std::max(hi, h);
      for (const Point& c : t.corners)
        if (c.y > ya && c.y < yb) {
          t.row(c.y, l, h, RowRange::kOutward);
          lo = std::min(lo, l);
          hi = std::max(hi, h);
        }
    }
    const double cy = 0.5 * double(j * step + last(j, patch.height));
    for (int64_t i = std::max<int64_t>(lo, 0) / step; i * step <= hi; ++i) {
      const size_t k = size_t(j) * size_t(s.columns) + size_t(i);
      const double cx = 0.5 * double(i * step + last(i, patch.width));
      auto above = [&](double x, double y) {  // the block's plane above the triangle's
        return double(s.a[k]) + double(s.bx[k]) * (x - cx) + double(s.by[k]) * (y - cy) -
               (t.za + t.gx * (x - double(t.corners[0].x)) + t.gy * (y - double(t.corners[0].y)));
      };
      double top, bottom;
      if (step == 1) {
        // One sample (inside the triangle: this row's exact range), as a dense patch measures it.
        top = bottom = double(s.a[k]) - t.at(i, j);
      } else {
        clipToRectangle(t, double(i * step), double(last(i, patch.width)), double(j * step),
                        double(last(j, patch.height)), polygon, scratch);
        if (polygon.empty()) continue;
        top = -std::numeric_limits<double>::infinity();
        bottom = -top;
        for (const auto& v : polygon) {
          const double d = above(v[0], v[1]);
          top = std::max(top, d);
          bottom = std::min(bottom, d);
        }
      }
      const double d = std::max(top + double(s.hi[k]), -(bottom + double(s.lo[k])));
      if (d > worst) {
        worst = d;
        if (worst > limit) return worst;
      }
    }
  }
  return worst;
}

}  // namespace

SampleBlocks makeSampleBlocks(int32_t width, int32_t height, int32_t step,
                              const std::function<float(int32_t, int32_t)>& sample) {
  SampleBlocks b;
  b.step = step;
  b.columns = (width + step - 1) / step;
  b.rows = (height + step - 1) / step;
  const size_t n = size_t(b.columns) * size_t(b.rows);
  b.a.resize(n);
  b.bx.resize(n);
  b.by.resize(n);
  b.lo.resize(n);
  b.hi.resize(n);
  std::vector<float> block(size_t(step) * size_t(step));
  for (int32_t j = 0; j < b.rows; ++j)
    for (int32_t i = 0; i < b.columns; ++i) {
      const int32_t x0 = i * step, y0 = j * step;
      const int32_t w = std::min(step, width - x0), h = std::min(step, height - y0);
      for (int32_t y = 0; y < h; ++y)
        for (int32_t x = 0; x < w; ++x)
          block[size_t(y) * size_t(w) + size_t(x)] = sample(x0 + x, y0 + y);
      auto at = [&](int32_t x, int32_t y) {
        return double(block[size_t(y) * size_t(w) + size_t(x)]);
      };
      // Mean height, and mean slopes from the first to the last column and row.
      double mean = 0.0, west = 0.0, east = 0.0, south = 0.0, north = 0.0;
      for (int32_t y = 0; y < h; ++y)
        for (int32_t x = 0; x < w; ++x) mean += at(x, y);
      mean /= double(w) * double(h);
      for (int32_t y = 0; y < h; ++y) {
        west += at(0, y);
        east += at(w - 1, y);
      }
      for (int32_t x = 0; x < w; ++x) {
        south += at(x, 0);
        north += at(x, h - 1);
      }
      const double bx = w > 1 ? (east - west) / double(h) / double(w - 1) : 0.0;
      const double by = h > 1 ? (north - south) / double(w) / double(h - 1) : 0.0;
      const size_t k = size_t(j) * size_t(b.columns) + size_t(i);
      b.a[k] = float(mean);
      b.bx[k] = float(bx);
      b.by[k] = float(by);
      // The residuals from the plane as stored (float), rounded outward.
      const double cx = 0.5 * double(w - 1), cy = 0.5 * double(h - 1);
      double lo = std::numeric_limits<double>::infinity(), hi = -lo;
      for (int32_t y = 0; y < h; ++y)
        for (int32_t x = 0; x < w; ++x) {
          const double r = at(x, y) - (double(b.a[k]) + double(b.bx[k]) * (double(x) - cx) +
                                       double(b.by[k]) * (double(y) - cy));
          lo = std::min(lo, r);
          hi = std::max(hi, r);
        }
      b.lo[k] = std::nextafter(float(lo), -std::numeric_limits<float>::infinity());
      b.hi[k] = std::nextafter(float(hi), std::numeric_limits<float>::infinity());
      if (w == 1 && h == 1) b.lo[k] = b.hi[k] = 0.0f;  // one sample: its own plane, exactly
    }
  return b;
}

double triangleError(const GridPatch& patch, uint16_t ia, uint16_t ib, uint16_t ic, double limit) {
  const Plane t(patch, ia, ib, ic);
  return patch.sparse() ? blockError(patch, t, limit) : scannedError(patch, t, limit);
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
