#pragma once
// Exact vertical error of a bintree triangle against the samples it covers.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include "terralod/core/bintree.h"

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

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

/// roundUp(baseAbove + max(0, d)) and roundUp(baseBelow + max(0, -d)) (bases >= 0): the two
/// sides of a triangle's bound from its midpoint's offset d. The sign of d is a coin toss on
/// rough terrain, so the SSE2 path takes no branch on it; both paths give the same floats.
inline TriangleErrorBounds roundUpSides(double d, double baseAbove, double baseBelow) {
#if defined(__SSE2__)
  const __m128d offsets = _mm_max_pd(_mm_set_pd(-d, d), _mm_setzero_pd());
  const __m128d v = _mm_add_pd(_mm_set_pd(baseBelow, baseAbove), offsets);
  const __m128 f = _mm_cvtpd_ps(v);
  // Where the nearest float fell below v, the next float up: bits + 1 (v >= 0).
  const __m128i low = _mm_castpd_si128(_mm_cmplt_pd(_mm_cvtps_pd(f), v));
  const __m128i bits =
      _mm_sub_epi32(_mm_castps_si128(f), _mm_shuffle_epi32(low, _MM_SHUFFLE(2, 2, 2, 0)));
  return {_mm_cvtss_f32(_mm_castsi128_ps(bits)),
          _mm_cvtss_f32(_mm_castsi128_ps(_mm_shuffle_epi32(bits, 1)))};
#else
  return {roundUp(baseAbove + std::max(0.0, d)), roundUp(baseBelow + std::max(0.0, -d))};
#endif
}

/// Scans the samples of `heights` (row-major, `stride` per row, local coordinates) inside the
/// closed triangle whose coordinates are <= (realX, realY). Triangle edges must be axis-aligned
/// or diagonal (as all bintree triangles are), which keeps every row span integer-exact.
TriangleErrorBounds scanTriangle(const float* heights, int32_t stride, const BinTriangle& t,
                                 int32_t realX, int32_t realY);

}  // namespace terralod
