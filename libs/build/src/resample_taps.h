#pragma once
// The filter taps of texel resampling (texel_tile.cpp) and the two sums every resampled texel
// is made of, shared by resampleTile and MosaicBuilder so that both add the same products in
// the same order (and so give the same floats).

#include <cstddef>
#include <cstdint>
#include <vector>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "terralod/build/texel_tile.h"

namespace terralod {

/// Filter taps of one output texel along one axis: source texels first, first + 1, ...
struct Taps {
  uint32_t first = 0;
  std::vector<float> weights;
};

/// Taps of every output texel from `from` to `to` texels (cached per thread).
const std::vector<Taps>& tapsFor(uint32_t from, uint32_t to, Placement placement);

/// The column pass: one source row's share of a row of column sums. Four at a time with SSE2
/// (each sum the same two operations either way: -O2 does not vectorise a loop of unknown
/// length by itself).
inline void addWeightedRow(float* sums, const float* row, float weight, size_t count) {
  size_t k = 0;
#if defined(__SSE2__)
  const __m128 w = _mm_set1_ps(weight);
  for (; k + 4 <= count; k += 4)
    _mm_storeu_ps(sums + k,
                  _mm_add_ps(_mm_loadu_ps(sums + k), _mm_mul_ps(w, _mm_loadu_ps(row + k))));
#endif
  for (; k < count; ++k) sums[k] += weight * row[k];
}

// One- and three-channel texels with their sums in registers (the compiler cannot tell that
// `out` aliases nothing), added in the same order as the general loop below.
inline void resampleTexel1(float* out, const float* sums, const Taps& taps) {
  float a = out[0];
  const float* w = taps.weights.data();
  for (size_t i = 0, n = taps.weights.size(); i < n; ++i) a += w[i] * sums[i];
  out[0] = a;
}
inline void resampleTexel3(float* out, const float* sums, const Taps& taps) {
  float a = out[0], b = out[1], d = out[2];
  const float* w = taps.weights.data();
  for (size_t i = 0, n = taps.weights.size(); i < n; ++i, sums += 3) {
    a += w[i] * sums[0];
    b += w[i] * sums[1];
    d += w[i] * sums[2];
  }
  out[0] = a;
  out[1] = b;
  out[2] = d;
}

/// The row pass: one output texel (`c` channels, zero before) from the column sums, `sums`
/// pointing at the sums of its first tap.
inline void resampleTexel(float* out, const float* sums, const Taps& taps, uint32_t c) {
  if (c == 1) return resampleTexel1(out, sums, taps);
  if (c == 3) return resampleTexel3(out, sums, taps);
  for (size_t i = 0; i < taps.weights.size(); ++i, sums += c) {
    const float w = taps.weights[i];
    for (uint32_t ch = 0; ch < c; ++ch) out[ch] += w * sums[ch];
  }
}

}  // namespace terralod
