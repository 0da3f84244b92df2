#pragma once
// Decoding stored texture tiles back to plain texels on the CPU, for tools that need pixels
// rather than GPU blocks (`terralod export` assembles one colour image from a level's tiles).
// BC1 as the S3TC specification defines it: two RGB565 end points, four colours when the first
// is numerically greater, else three and black (alpha is ignored: terralod's colour is RGB).

#include <cstdint>
#include <span>
#include <vector>

#include "terralod/format/texture_codec.h"

namespace terralod {

/// One mip level of a BC1 layer of `size` texels (max(1, layerSize >> m)) decoded to RGB8,
/// row-major with the stored row order kept: row 0 is the southern one (docs/format.md),
/// texel (x, y) at [(y * size + x) * 3]. Empty when `blocks` is not exactly the level's bytes.
std::vector<uint8_t> decodeBc1Rgb(std::span<const uint8_t> blocks, uint32_t size);

/// One mip level of a BC5 layer decoded to RG8 as RGTC2 (unsigned) defines it: per channel two
/// 8-bit end points, eight values when the first is greater, else six, 0 and 255; texel (x, y)
/// at [(y * size + x) * 2], row 0 the southern one. Empty when `blocks` is not exactly the
/// level's bytes.
std::vector<uint8_t> decodeBc5Rg(std::span<const uint8_t> blocks, uint32_t size);

/// One mip level of a BC4 layer decoded to R8 as RGTC1 (unsigned) defines it (decodeBc5Rg's
/// channel); texel (x, y) at [y * size + x].
std::vector<uint8_t> decodeBc4R(std::span<const uint8_t> blocks, uint32_t size);

}  // namespace terralod
