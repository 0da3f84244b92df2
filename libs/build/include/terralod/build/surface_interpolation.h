#pragma once
// Heights of a triangulated surface at grid samples, computed so that a sample on an edge gets
// the same value from both triangles that share the edge (and from two chunks that share a
// side): on an edge, the height is the edge's own linear interpolation from its lower end
// (lexicographically smaller grid point), never the triangle's barycentric sum.

#include <algorithm>
#include <cstdint>

#include "terralod/core/sample_raster.h"

namespace terralod {

struct SurfaceCorner {
  int32_t x = 0, y = 0;
  double z = 0.0;
};

inline double lerpOnSegment(double za, double zb, double f) {
  return za + f * (zb - za);
}

/// Height at grid point (x, y) on the segment a-b (inclusive).
inline double heightOnEdge(const SurfaceCorner& a, const SurfaceCorner& b, int32_t x, int32_t y) {
  const bool aFirst = a.x < b.x || (a.x == b.x && a.y < b.y);
  const SurfaceCorner& lo = aFirst ? a : b;
  const SurfaceCorner& hi = aFirst ? b : a;
  if (x == hi.x && y == hi.y) return hi.z;
  const double f = hi.x != lo.x ? double(x - lo.x) / double(hi.x - lo.x)
                                : double(y - lo.y) / double(hi.y - lo.y);
  return lerpOnSegment(lo.z, hi.z, f);
}

/// Calls emit(x, y, z) for every grid point of the triangle (edges included) inside the
/// rectangle [x0, x1] x [y0, y1]. Either winding; degenerate triangles emit nothing.
template <typename Emit>
void rasterizeTriangle(const SurfaceCorner (&c)[3], int32_t x0, int32_t y0, int32_t x1, int32_t y1,
                       Emit&& emit) {
  auto orient = [](const SurfaceCorner& a, const SurfaceCorner& b, int64_t x, int64_t y) {
    return (int64_t(b.x) - a.x) * (y - a.y) - (int64_t(b.y) - a.y) * (x - a.x);
  };
  int64_t area = orient(c[0], c[1], c[2].x, c[2].y);
  if (area == 0) return;
  const int s = area > 0 ? 1 : -1;
  area *= s;
  const double inv = 1.0 / double(area);
  forEachTriangleRow(c[0], c[1], c[2], x0, x1, y0, y1, [&](int64_t y, int64_t lo, int64_t hi) {
    for (int64_t x = lo; x <= hi; ++x) {
      const int64_t w0 = s * orient(c[1], c[2], x, y), w1 = s * orient(c[2], c[0], x, y),
                    w2 = s * orient(c[0], c[1], x, y);
      const auto gx = int32_t(x), gy = int32_t(y);
      double z;
      if (w0 == 0)
        z = heightOnEdge(c[1], c[2], gx, gy);
      else if (w1 == 0)
        z = heightOnEdge(c[2], c[0], gx, gy);
      else if (w2 == 0)
        z = heightOnEdge(c[0], c[1], gx, gy);
      else
        z = (double(w0) * c[0].z + double(w1) * c[1].z + double(w2) * c[2].z) * inv;
      emit(gx, gy, z);
    }
  });
}

}  // namespace terralod
