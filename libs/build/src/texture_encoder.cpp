#include "terralod/build/texture_encoder.h"

#include <algorithm>
#include <cmath>

#include <cstring>

#include "alpha_block.h"
#include "texel_bytes.h"

#define STB_DXT_STATIC
#define STB_DXT_IMPLEMENTATION
#include <stb_dxt.h>

namespace terralod {
namespace {

// Encodes one mip level of 8-bit texels (`bytes` per texel, row-major) block by block;
// texels past the edge repeat the last row/column. `bytes` is a template argument so that
// gathering a row of a block is one load and one store, not a call to memcpy.
template <uint32_t bytes, typename Block>
std::vector<uint8_t> encodeBlocks(const std::vector<uint8_t>& texels, uint32_t size,
                                  size_t blockBytes, Block&& block) {
  const uint32_t blocks = (size + 3) / 4;
  std::vector<uint8_t> out(size_t(blocks) * blocks * blockBytes);
  uint8_t gathered[16 * 4];
  for (uint32_t by = 0; by < blocks; ++by)
    for (uint32_t bx = 0; bx < blocks; ++bx) {
      const bool wholeRows = bx * 4 + 4 <= size;
      for (uint32_t j = 0; j < 4; ++j) {
        const uint8_t* row = texels.data() + size_t(std::min(by * 4 + j, size - 1)) * size * bytes;
        if (wholeRows) {
          std::memcpy(gathered + j * 4 * bytes, row + size_t(bx) * 4 * bytes, 4 * bytes);
          continue;
        }
        for (uint32_t i = 0; i < 4; ++i)
          std::memcpy(gathered + (j * 4 + i) * bytes,
                      row + size_t(std::min(bx * 4 + i, size - 1)) * bytes, bytes);
      }
      block(out.data() + (size_t(by) * blocks + bx) * blockBytes, gathered);
    }
  return out;
}

TextureLayer encodeLayer(const TexelTile& tile, TextureLayerKind kind, TextureEncoding encoding,
                         uint8_t flags, std::vector<uint8_t> level0) {
  TextureLayer layer;
  layer.kind = kind;
  layer.encoding = encoding;
  layer.flags = flags;
  layer.size = tile.size;
  const uint32_t mips = mipCount(tile.size);
  layer.mips.push_back(level0.empty() ? encodeLevel(tile, encoding) : std::move(level0));
  TexelTile level;
  for (uint32_t m = 1; m < mips; ++m) {
    level = nextMip(m == 1 ? tile : level, mipSize(tile.size, m));
    layer.mips.push_back(encodeLevel(level, encoding));
  }
  return layer;
}

}  // namespace

TexelTile nextMip(const TexelTile& above, uint32_t size) {
  if (size >= 2) return mipTile(above, size);
  TexelTile one(1, above.channels);  // the 1x1 level: the mean
  for (uint32_t y = 0; y < above.size; ++y)
    for (uint32_t x = 0; x < above.size; ++x)
      for (uint32_t c = 0; c < above.channels; ++c)
        one.values[c] += above.at(x, y)[c] / float(above.size * above.size);
  return one;
}

std::vector<uint8_t> encodeLevel(const TexelTile& level, TextureEncoding encoding) {
  const size_t n = size_t(level.size) * level.size;
  if (encoding == TextureEncoding::kBc1) {
    std::vector<uint8_t> rgba(n * 4, 255);
    for (size_t i = 0; i < n; ++i)
      for (size_t c = 0; c < 3; ++c) rgba[i * 4 + c] = unitToByte(level.values[i * 3 + c]);
    return encodeBlocks<4>(rgba, level.size, 8, [](uint8_t* out, uint8_t* t) {
      stb_compress_dxt_block(out, t, 0, STB_DXT_NORMAL);
    });
  }
  if (encoding == TextureEncoding::kBc4) {
    std::vector<uint8_t> r(n);
    unitsToBytes(level.values.data(), n, r.data());
    return encodeBlocks<1>(r, level.size, 8,
                           [](uint8_t* out, uint8_t* t) { encodeBc4Block(out, t); });
  }
  std::vector<uint8_t> rg(n * 2);
  normalsToRg(level.values.data(), n, rg.data());
  return encodeBlocks<2>(rg, level.size, 16,
                         [](uint8_t* out, uint8_t* t) { encodeBc5Block(out, t); });
}

TextureLayer encodeColorLayer(const TexelTile& tile, uint8_t flags, std::vector<uint8_t> level0) {
  return encodeLayer(tile, TextureLayerKind::kColor, TextureEncoding::kBc1, flags,
                     std::move(level0));
}

TextureLayer encodeNormalLayer(const TexelTile& tile, uint8_t flags, std::vector<uint8_t> level0) {
  return encodeLayer(tile, TextureLayerKind::kNormal, TextureEncoding::kBc5, flags,
                     std::move(level0));
}

std::vector<uint8_t> concatBlocks(const std::array<const std::vector<uint8_t>*, 4>& children,
                                  uint32_t childSize, TextureEncoding encoding) {
  if (childSize % 4 != 0) return {};
  for (const auto* c : children)
    if (!c) return {};
  const size_t blockBytes = mipBytes(encoding, 4, 0);
  const uint32_t childBlocks = childSize / 4, parentBlocks = 2 * childBlocks;
  std::vector<uint8_t> out(size_t(parentBlocks) * parentBlocks * blockBytes);
  for (uint32_t q = 0; q < 4; ++q) {
    const std::vector<uint8_t>& child = *children[q];
    const uint32_t ox = (q & 1) * childBlocks, oy = (q >> 1) * childBlocks;
    for (uint32_t by = 0; by < childBlocks; ++by)
      std::memcpy(out.data() + ((size_t(oy + by) * parentBlocks) + ox) * blockBytes,
                  child.data() + size_t(by) * childBlocks * blockBytes, childBlocks * blockBytes);
  }
  return out;
}

std::vector<uint8_t> mosaicBlocks(const std::array<const std::vector<uint8_t>*, 4>& children,
                                  uint32_t childSize, TextureEncoding encoding) {
  if ((childSize - 1) % 4 != 0) return {};
  for (const auto* c : children)
    if (!c) return {};
  const size_t blockBytes = mipBytes(encoding, 4, 0);
  const uint32_t childBlocks = (childSize + 3) / 4, step = (childSize - 1) / 4;
  const uint32_t parentBlocks = (2 * childSize - 1 + 3) / 4;
  std::vector<uint8_t> out(size_t(parentBlocks) * parentBlocks * blockBytes);
  for (uint32_t by = 0; by < parentBlocks; ++by)
    for (uint32_t bx = 0; bx < parentBlocks; ++bx) {
      const uint32_t qx = bx >= step ? 1 : 0, qy = by >= step ? 1 : 0;
      const std::vector<uint8_t>& child = *children[qy * 2 + qx];
      const size_t from = (size_t(by - qy * step) * childBlocks + (bx - qx * step)) * blockBytes;
      std::memcpy(out.data() + (size_t(by) * parentBlocks + bx) * blockBytes, child.data() + from,
                  blockBytes);
    }
  return out;
}

}  // namespace terralod
