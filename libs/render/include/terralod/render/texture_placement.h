#pragma once
// Where a chunk texture's mip levels keep their texels. Level 0 is edge-aligned (texel i at
// i / (size - 1) of the chunk's side), and so is every mip the builder computes from the level
// above. But a parent's mip levels are its children's side by side wherever the sizes allow
// (docs/format.md, "Mip placement"): mip m of a parent that holds its children unresampled
// (size 2c - 1) is their mip m, of one that halves them (size c) their mip m + 1, recursively.
// Such a mip is a mosaic of 2^k x 2^k pieces, each a descendant tile's mip placed for that
// descendant's size, not for the whole tile's. GL's own sampling assumes the whole tile's
// placement; the shader samples these levels piece by piece instead, so a parent shows exactly
// its children's texels at every mip, and a split or merge changes nothing in the picture.

#include <cstdint>
#include <span>
#include <vector>

namespace terralod {

/// Mip m of a layer is `pieces` x `pieces` tiles of `pieceSize` texels at their mip `pieceMip`,
/// each placed for its own size. pieces == 1, pieceSize == size, pieceMip == m: the usual.
struct MipPlacement {
  uint32_t pieces = 1;
  uint32_t pieceSize = 0;
  uint32_t pieceMip = 0;
  friend bool operator==(const MipPlacement&, const MipPlacement&) = default;
};

/// The placement of every mip of every level's layer, given the layer's size at each level
/// (root first, leaves last), by the builder's rule.
std::vector<std::vector<MipPlacement>> mipPlacements(std::span<const uint32_t> sizes);

/// Whether a level's mips need piecewise sampling: some of them hold a level kept unresampled
/// (each such level shifts texels by up to half a level-0 texel from where GL samples them).
/// Levels that only halve their children shift them by far less (image pops of a few
/// hundredths of a grey level measured), and GL's own sampling is kept there: it is cheaper.
bool needsPiecewiseSampling(std::span<const MipPlacement> mips);

/// The shader's table: 16 entries per level and layer kind (colour, normal), level by level:
/// entry m = log2(pieces) | pieceMip << 4 | pieceSize << 8, entry 0 also bit 31 when the level
/// needs piecewise sampling. Levels absent from one of the lists get standard entries.
std::vector<uint32_t> packPlacements(std::span<const uint32_t> colorSizes,
                                     std::span<const uint32_t> normalSizes);

inline constexpr uint32_t kPlacementEntries = 16;  ///< per level and kind (mip count <= 13)

}  // namespace terralod
