#pragma once
// The filter taps of texel resampling (texel_tile.cpp) and the two sums every resampled texel
// is made of, shared by resampleTile and MosaicBuilder so that both add the same products in
// the same order (and so give the same floats).

#include <cstddef>
#include <cstdint>
#include <vector>

#include "terralod/build/texel_tile.h"

namespace terralod {

/// Filter taps of one output texel along one axis: source texels first, first + 1, ...
struct Taps {
  uint32_t first = 0;
  std::vector<float> weights;
};

/// Taps of every output texel from `from` to `to` texels (cached per thread).
const std::vector<Taps>& tapsFor(uint32_t from, uint32_t to, Placement placement);

/// The column pass: one source row's share of a row of column sums.
inline void addWeightedRow(float* sums, const float* row, float weight, size_t count) {
  for (size_t k = 0; k < count; ++k) sums[k] += weight * row[k];
}

/// The row pass: one output texel (`c` channels, zero before) from the column sums, `sums`
/// pointing at the sums of its first tap.
inline void resampleTexel(float* out, const float* sums, const Taps& taps, uint32_t c) {
  for (size_t i = 0; i < taps.weights.size(); ++i, sums += c) {
    const float w = taps.weights[i];
    for (uint32_t ch = 0; ch < c; ++ch) out[ch] += w * sums[ch];
  }
}

}  // namespace terralod
