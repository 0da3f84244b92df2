#pragma once
// A chunk part's triangles from index `from` on, each rotated to start at its lowest index:
// meshoptimizer's index codec may rotate the triangles it stores (never reverse them), so
// geometry compares this way across codecs.

#include <algorithm>
#include <array>
#include <cstdint>
#include <vector>

#include "terralod/format/chunk_codec.h"

namespace terralod::test {

inline std::vector<std::array<uint32_t, 3>> rotatedTriangles(const ChunkPart& part,
                                                             size_t from = 0) {
  std::vector<std::array<uint32_t, 3>> out;
  for (size_t k = from; k + 2 < part.indices.size(); k += 3) {
    std::array<uint32_t, 3> t = {part.indices[k], part.indices[k + 1], part.indices[k + 2]};
    std::rotate(t.begin(), std::min_element(t.begin(), t.end()), t.end());
    out.push_back(t);
  }
  return out;
}

}  // namespace terralod::test
