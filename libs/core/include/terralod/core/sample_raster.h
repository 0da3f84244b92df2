#pragma once
// Visits the integer sample points inside a triangle (closed) with the linearly interpolated
// height there. Exact integer inside tests, so shared edges are visited by both neighbours.

#include <algorithm>
#include <cstdint>
#include <limits>

namespace terralod {

struct SampleVertex {
  int64_t x, y;
  double z;
};

/// Calls row(y, lo, hi) for every row y in [minY, maxY] that holds integer points of the
/// closed triangle (a, b, c) with x in [minX, maxX]: those are x = lo .. hi. Either winding
/// (any type with x and y); degenerate triangles visit nothing.
template <typename Point, typename Row>
void forEachTriangleRow(const Point& pa, const Point& pb, const Point& pc, int64_t minX,
                        int64_t maxX, int64_t minY, int64_t maxY, Row&& row) {
  struct P {
    int64_t x, y;
  };
  P a{pa.x, pa.y}, b{pb.x, pb.y}, c{pc.x, pc.y};
  const int64_t area = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
  if (area == 0) return;
  if (area < 0) std::swap(b, c);
  const P v[3] = {a, b, c};
  const int64_t y0 = std::max(minY, std::min({a.y, b.y, c.y}));
  const int64_t y1 = std::min(maxY, std::max({a.y, b.y, c.y}));
  const int64_t x0 = std::max(minX, std::min({a.x, b.x, c.x}));
  const int64_t x1 = std::min(maxX, std::max({a.x, b.x, c.x}));
  if (x0 > x1) return;  // wholly left or right of the window
  for (int64_t y = y0; y <= y1; ++y) {
    int64_t lo = x0, hi = x1;
    // Counter-clockwise edge p->q keeps points with (q-p) x (s-p) >= 0, linear in x.
    for (int e = 0; e < 3 && lo <= hi; ++e) {
      const P& p = v[e];
      const P& q = v[(e + 1) % 3];
      const int64_t dx = q.x - p.x, dy = q.y - p.y;
      const int64_t k = dx * (y - p.y) + dy * p.x;  // condition: dy * x <= k
      if (dy == 0) {
        if (dx * (y - p.y) < 0) lo = hi + 1;
      } else if (dy > 0) {
        const int64_t bound = k >= 0 ? k / dy : -((-k + dy - 1) / dy);  // floor(k / dy)
        hi = std::min(hi, bound);
      } else {
        const int64_t n = -dy, m = -k;                                 // condition: n * x >= m
        const int64_t bound = m >= 0 ? (m + n - 1) / n : -((-m) / n);  // ceil(m / n)
        lo = std::max(lo, bound);
      }
    }
    if (lo <= hi) row(y, lo, hi);
  }
}

/// Calls visit(x, y, z) for every integer (x, y) inside triangle (a, b, c) with
/// x in [minX, maxX] and y in [minY, maxY]. Degenerate triangles visit nothing.
template <typename Visit>
void rasterizeTriangle(SampleVertex a, SampleVertex b, SampleVertex c, int64_t minX, int64_t maxX,
                       int64_t minY, int64_t maxY, Visit&& visit) {
  int64_t area = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
  if (area == 0) return;
  if (area < 0) {
    std::swap(b, c);
    area = -area;
  }
  forEachTriangleRow(a, b, c, minX, maxX, minY, maxY, [&](int64_t y, int64_t lo, int64_t hi) {
    for (int64_t x = lo; x <= hi; ++x) {
      const double wa = double((b.x - x) * (c.y - y) - (b.y - y) * (c.x - x)) / double(area);
      const double wb = double((c.x - x) * (a.y - y) - (c.y - y) * (a.x - x)) / double(area);
      visit(x, y, wa * a.z + wb * b.z + (1.0 - wa - wb) * c.z);
    }
  });
}

}  // namespace terralod
