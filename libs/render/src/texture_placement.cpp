#include "terralod/render/texture_placement.h"

#include <algorithm>
#include <bit>

#include "terralod/format/texture_codec.h"

namespace terralod {

std::vector<std::vector<MipPlacement>> mipPlacements(std::span<const uint32_t> sizes) {
  std::vector<std::vector<MipPlacement>> out(sizes.size());
  // Leaves up, mirroring the builder: a level's mip m is its children's mip `from` side by side
  // when both have it and two of theirs make one of its.
  for (size_t level = sizes.size(); level-- > 0;) {
    const uint32_t size = sizes[level], mips = mipCount(size);
    std::vector<MipPlacement>& own = out[level];
    for (uint32_t m = 0; m < mips; ++m) own.push_back({1, size, m});
    if (level + 1 == sizes.size()) continue;
    const uint32_t child = sizes[level + 1];
    const std::vector<MipPlacement>& below = out[level + 1];
    const bool unresampled = 2 * child - 1 == size, halved = child == size;
    for (uint32_t m = 1; m < mips; ++m) {
      const uint32_t from = unresampled ? m : halved ? m + 1 : 0;
      if (from == 0 || from >= below.size() || 2 * mipSize(child, from) != mipSize(size, m))
        continue;
      own[m] = below[from];
      own[m].pieces *= 2;
    }
  }
  return out;
}

bool needsPiecewiseSampling(std::span<const MipPlacement> mips) {
  // Halving alone (pieceMip = m + log2(pieces)) moves texels by at most a quarter of a level-0
  // texel; every level held unresampled adds up to half of one.
  for (uint32_t m = 0; m < mips.size(); ++m)
    if (mips[m].pieceMip < m + uint32_t(std::countr_zero(mips[m].pieces))) return true;
  return false;
}

std::vector<uint32_t> packPlacements(std::span<const uint32_t> colorSizes,
                                     std::span<const uint32_t> normalSizes) {
  const size_t levels = std::max(colorSizes.size(), normalSizes.size());
  std::vector<uint32_t> table(levels * 2 * kPlacementEntries, 0);
  const std::span<const uint32_t> kinds[2] = {colorSizes, normalSizes};
  for (size_t kind = 0; kind < 2; ++kind) {
    const auto placements = mipPlacements(kinds[kind]);
    for (size_t level = 0; level < placements.size(); ++level) {
      uint32_t* entries = &table[(level * 2 + kind) * kPlacementEntries];
      const auto& mips = placements[level];
      for (size_t m = 0; m < mips.size() && m < kPlacementEntries; ++m)
        entries[m] = uint32_t(std::countr_zero(mips[m].pieces)) | mips[m].pieceMip << 4 |
                     mips[m].pieceSize << 8;
      if (needsPiecewiseSampling(mips)) entries[0] |= 0x80000000u;
    }
  }
  return table;
}

}  // namespace terralod
