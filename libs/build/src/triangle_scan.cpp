#include "triangle_scan.h"

#include <algorithm>

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

  // Edges not parallel to the rows, as x = x(first row) + slope * (y - first row); bintree
  // edges are axis-aligned or diagonal, so slopes are -1, 0 or 1 and spans are exact.
  struct Edge {
    int32_t yLo, yHi, xAtLo, slope;
  };
  Edge edges[3];
  int edgeCount = 0;
  for (int e = 0; e < 3; ++e) {
    GridPoint a = p[e], b = p[(e + 1) % 3];
    if (a.y == b.y) continue;
    if (a.y > b.y) std::swap(a, b);
    edges[edgeCount++] = {a.y, b.y, a.x, (b.x - a.x) / (b.y - a.y)};
  }
  const int32_t yLo = std::min({p[0].y, p[1].y, p[2].y});
  const int32_t yHi = std::min(std::max({p[0].y, p[1].y, p[2].y}), realY);
  double above = 0.0, below = 0.0;
  for (int32_t y = yLo; y <= yHi; ++y) {
    int32_t xl = INT32_MAX, xr = INT32_MIN;
    for (int e = 0; e < edgeCount; ++e) {
      if (y < edges[e].yLo || y > edges[e].yHi) continue;
      const int32_t x = edges[e].xAtLo + edges[e].slope * (y - edges[e].yLo);
      xl = std::min(xl, x);
      xr = std::max(xr, x);
    }
    xr = std::min(xr, realX);
    if (xl > xr) continue;
    // max/min of h - gx * x over the span, with four independent chains.
    const float* row = heights + size_t(y) * stride;
    double hi[4] = {-1e300, -1e300, -1e300, -1e300}, lo[4] = {1e300, 1e300, 1e300, 1e300};
    int32_t x = xl;
    for (; x + 3 <= xr; x += 4)
      for (int k = 0; k < 4; ++k) {
        const double r = double(row[x + k]) - gx * double(x + k);
        hi[k] = r > hi[k] ? r : hi[k];
        lo[k] = r < lo[k] ? r : lo[k];
      }
    for (; x <= xr; ++x) {
      const double r = double(row[x]) - gx * double(x);
      hi[0] = r > hi[0] ? r : hi[0];
      lo[0] = r < lo[0] ? r : lo[0];
    }
    const double rowBase = z0 + gy * (y - y0) - gx * x0;
    above = std::max(above, std::max({hi[0], hi[1], hi[2], hi[3]}) - rowBase);
    below = std::max(below, rowBase - std::min({lo[0], lo[1], lo[2], lo[3]}));
  }
  return {roundUp(above), roundUp(below)};
}

}  // namespace terralod
