#pragma once
// Float texels to the 8-bit values block compression takes: values in [0, 1] to bytes, and
// normals (any length) to the bytes of their unit vector's x and y. The same bytes whether the
// SSE2 path (every x86-64: four texels at once) or the portable loop runs; the vector path
// does the same IEEE operations in the same order (no fused multiply-add), so nothing but the
// speed depends on which.

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace terralod {

/// v in [0, 1] to 0 .. 255, rounded; outside the range clamped.
inline uint8_t unitToByte(float v) {
  return uint8_t(std::min(std::max(v * 255.0f + 0.5f, 0.0f), 255.0f));
}

/// One normal's (3 floats, any length; zero gives 0.5, 0.5) unit x and y as bytes.
inline void normalToRg(const float* v, uint8_t* rg) {
  const float len = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  const float inv = len > 0 ? 1.0f / len : 0.0f;
  rg[0] = unitToByte(0.5f * (v[0] * inv + 1.0f));
  rg[1] = unitToByte(0.5f * (v[1] * inv + 1.0f));
}

namespace texel_bytes {

inline void unitsToBytesPortable(const float* v, size_t n, uint8_t* out) {
  for (size_t i = 0; i < n; ++i) out[i] = unitToByte(v[i]);
}
inline void normalsToRgPortable(const float* xyz, size_t n, uint8_t* rg) {
  for (size_t i = 0; i < n; ++i) normalToRg(xyz + 3 * i, rg + 2 * i);
}

#if defined(__SSE2__)
// unitToByte of four values, as four int32 lanes.
inline __m128i unitsToInts(__m128 v) {
  const __m128 scaled = _mm_add_ps(_mm_mul_ps(v, _mm_set1_ps(255.0f)), _mm_set1_ps(0.5f));
  return _mm_cvttps_epi32(_mm_min_ps(_mm_max_ps(scaled, _mm_setzero_ps()), _mm_set1_ps(255.0f)));
}
#endif

}  // namespace texel_bytes

/// unitToByte of v[0 .. n - 1] into out.
inline void unitsToBytes(const float* v, size_t n, uint8_t* out) {
  size_t i = 0;
#if defined(__SSE2__)
  for (; i + 16 <= n; i += 16) {
    __m128i q[4];
    for (int k = 0; k < 4; ++k) q[k] = texel_bytes::unitsToInts(_mm_loadu_ps(v + i + 4 * k));
    const __m128i bytes =
        _mm_packus_epi16(_mm_packs_epi32(q[0], q[1]), _mm_packs_epi32(q[2], q[3]));
    _mm_storeu_si128(reinterpret_cast<__m128i*>(out + i), bytes);
  }
#endif
  texel_bytes::unitsToBytesPortable(v + i, n - i, out + i);
}

/// normalToRg of the n normals at xyz (3 floats each) into rg (2 bytes each).
inline void normalsToRg(const float* xyz, size_t n, uint8_t* rg) {
  size_t i = 0;
#if defined(__SSE2__)
  const __m128 half = _mm_set1_ps(0.5f), one = _mm_set1_ps(1.0f), zero = _mm_setzero_ps();
  for (; i + 4 <= n; i += 4) {
    const float* v = xyz + 3 * i;
    const __m128 x = _mm_setr_ps(v[0], v[3], v[6], v[9]), y = _mm_setr_ps(v[1], v[4], v[7], v[10]),
                 z = _mm_setr_ps(v[2], v[5], v[8], v[11]);
    const __m128 len =
        _mm_sqrt_ps(_mm_add_ps(_mm_add_ps(_mm_mul_ps(x, x), _mm_mul_ps(y, y)), _mm_mul_ps(z, z)));
    // 1 / len where len > 0, else 0 (the division's infinity masked away).
    const __m128 inv = _mm_and_ps(_mm_cmpgt_ps(len, zero), _mm_div_ps(one, len));
    const __m128i bx =
        texel_bytes::unitsToInts(_mm_mul_ps(half, _mm_add_ps(_mm_mul_ps(x, inv), one)));
    const __m128i by =
        texel_bytes::unitsToInts(_mm_mul_ps(half, _mm_add_ps(_mm_mul_ps(y, inv), one)));
    // Bytes x0 x1 x2 x3 y0 y1 y2 y3, then interleaved: x0 y0 x1 y1 ...
    const __m128i xy = _mm_packus_epi16(_mm_packs_epi32(bx, by), _mm_setzero_si128());
    _mm_storel_epi64(reinterpret_cast<__m128i*>(rg + 2 * i),
                     _mm_unpacklo_epi8(xy, _mm_srli_si128(xy, 4)));
  }
#endif
  texel_bytes::normalsToRgPortable(xyz + 3 * i, n - i, rg + 2 * i);
}

}  // namespace terralod
