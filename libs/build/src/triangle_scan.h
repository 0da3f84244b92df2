#pragma once
// Exact vertical error of a bintree triangle against the samples it covers.

#include <cmath>
#include <cstdint>
#include <limits>

#include "terralod/core/bintree.h"

namespace terralod {

/// Largest distance of covered samples above (h - plane) and below (plane - h) the plane
/// through the triangle's corners; zero when nothing lies off the plane.
struct TriangleErrorBounds {
  float above = 0.0f;
  float below = 0.0f;
};

/// The smallest float not below v, so stored errors never understate computed ones.
inline float roundUp(double v) {
  const float f = static_cast<float>(v);
  return double(f) >= v ? f : std::nextafter(f, std::numeric_limits<float>::infinity());
}

/// Scans the samples of `heights` (row-major, `stride` per row, local coordinates) inside the
/// closed triangle whose coordinates are <= (realX, realY). Triangle edges must be axis-aligned
/// or diagonal (as all bintree triangles are), which keeps every row span integer-exact.
TriangleErrorBounds scanTriangle(const float* heights, int32_t stride, const BinTriangle& t,
                                 int32_t realX, int32_t realY);

}  // namespace terralod
