#include "triangle_scan.h"

#include <algorithm>
#include <limits>

namespace terralod {

TriangleErrorBounds scanTriangle(const float* heights, int32_t stride, const BinTriangle& t,
                                 int32_t realX, int32_t realY) {
  const GridPoint p[3] = {t.a, t.b, t.apex};
  auto h = [&](GridPoint q) { return double(heights[size_t(q.y) * stride + q.x]); };
  // Plane z = z0 + gx (x - x0) + gy (y - y0) through the three corners.
  const double x0 = p[0].x, y0 = p[0].y, z0 = h(p[0]);
  const double x1 = p[1].x - x0, y1 = p[1].y - y0, z1 = h(p[1]) - z0;
  const double x2 = p[2].x - x0, y2 = p[2].y - y0, z2 = h(p[2]) - z0;
  const double det = x1 * y2 - x2 * y1;
  const double gx = (z1 * y2 - z2 * y1) / det;
  const double gy = (x1 * z2 - x2 * z1) / det;

  const int32_t yLo = std::min({p[0].y, p[1].y, p[2].y});
  const int32_t yHi = std::min(std::max({p[0].y, p[1].y, p[2].y}), realY);
  double above = 0.0, below = 0.0;
  for (int32_t y = yLo; y <= yHi; ++y) {
    int32_t xl = std::numeric_limits<int32_t>::max(), xr = std::numeric_limits<int32_t>::min();
    for (int e = 0; e < 3; ++e) {
      const GridPoint a = p[e], b = p[(e + 1) % 3];
      if (y < std::min(a.y, b.y) || y > std::max(a.y, b.y)) continue;
      if (a.y == b.y) {
        xl = std::min({xl, a.x, b.x});
        xr = std::max({xr, a.x, b.x});
      } else {
        const int32_t x = a.x + (y - a.y) * (b.x - a.x) / (b.y - a.y);
        xl = std::min(xl, x);
        xr = std::max(xr, x);
      }
    }
    xr = std::min(xr, realX);
    if (xl > xr) continue;
    const float* row = heights + size_t(y) * stride;
    const double rowBase = z0 + gy * (y - y0) - gx * x0;
    double rowAbove = 0.0, rowBelow = 0.0;
    for (int32_t x = xl; x <= xr; ++x) {
      const double r = double(row[x]) - (rowBase + gx * x);
      rowAbove = std::max(rowAbove, r);
      rowBelow = std::max(rowBelow, -r);
    }
    above = std::max(above, rowAbove);
    below = std::max(below, rowBelow);
  }
  return {roundUp(above), roundUp(below)};
}

}  // namespace terralod
