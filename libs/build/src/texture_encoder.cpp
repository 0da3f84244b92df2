#include "terralod/build/texture_encoder.h"

#include <algorithm>
#include <cmath>

#include <cstring>

#define STB_DXT_STATIC
#define STB_DXT_IMPLEMENTATION
#include <stb_dxt.h>

namespace terralod {
namespace {

uint8_t toByte(float v) {
  return uint8_t(std::clamp(v * 255.0f + 0.5f, 0.0f, 255.0f));
}

// Encodes one mip level block by block; texels past the edge repeat the last row/column.
template <typename Block>
std::vector<uint8_t> encodeBlocks(const TexelTile& tile, size_t blockBytes, Block&& block) {
  const uint32_t blocks = (tile.size + 3) / 4;
  std::vector<uint8_t> out(size_t(blocks) * blocks * blockBytes);
  for (uint32_t by = 0; by < blocks; ++by)
    for (uint32_t bx = 0; bx < blocks; ++bx) {
      const float* texels[16];
      for (uint32_t j = 0; j < 4; ++j)
        for (uint32_t i = 0; i < 4; ++i)
          texels[j * 4 + i] =
              tile.at(std::min(bx * 4 + i, tile.size - 1), std::min(by * 4 + j, tile.size - 1));
      block(out.data() + (size_t(by) * blocks + bx) * blockBytes, texels);
    }
  return out;
}

template <typename EncodeLevel>
TextureLayer encodeLayer(const TexelTile& tile, TextureLayerKind kind, TextureEncoding encoding,
                         uint8_t flags, EncodeLevel&& encodeLevel) {
  TextureLayer layer;
  layer.kind = kind;
  layer.encoding = encoding;
  layer.flags = flags;
  layer.size = tile.size;
  const uint32_t mips = mipCount(tile.size);
  layer.mips.push_back(encodeLevel(tile));
  TexelTile level;
  for (uint32_t m = 1; m < mips; ++m) {
    const TexelTile& above = m == 1 ? tile : level;
    const uint32_t size = mipSize(tile.size, m);
    if (size >= 2) {
      level = resampleTile(above, size);
    } else {  // the 1x1 level: the mean
      TexelTile one(1, above.channels);
      for (uint32_t y = 0; y < above.size; ++y)
        for (uint32_t x = 0; x < above.size; ++x)
          for (uint32_t c = 0; c < above.channels; ++c)
            one.values[c] += above.at(x, y)[c] / float(above.size * above.size);
      level = std::move(one);
    }
    layer.mips.push_back(encodeLevel(level));
  }
  return layer;
}

}  // namespace

TextureLayer encodeColorLayer(const TexelTile& tile, uint8_t flags) {
  return encodeLayer(tile, TextureLayerKind::kColor, TextureEncoding::kBc1, flags,
                     [](const TexelTile& level) {
                       return encodeBlocks(level, 8, [](uint8_t* out, const float* const* t) {
                         uint8_t rgba[64];
                         for (int i = 0; i < 16; ++i) {
                           rgba[i * 4 + 0] = toByte(t[i][0]);
                           rgba[i * 4 + 1] = toByte(t[i][1]);
                           rgba[i * 4 + 2] = toByte(t[i][2]);
                           rgba[i * 4 + 3] = 255;
                         }
                         stb_compress_dxt_block(out, rgba, 0, STB_DXT_NORMAL);
                       });
                     });
}

TextureLayer encodeNormalLayer(const TexelTile& tile, uint8_t flags) {
  return encodeLayer(tile, TextureLayerKind::kNormal, TextureEncoding::kBc5, flags,
                     [](const TexelTile& level) {
                       return encodeBlocks(level, 16, [](uint8_t* out, const float* const* t) {
                         uint8_t rg[32];
                         for (int i = 0; i < 16; ++i) {
                           const float* n = t[i];
                           const float len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
                           const float inv = len > 0 ? 1.0f / len : 0.0f;
                           rg[i * 2 + 0] = toByte(0.5f * (n[0] * inv + 1.0f));
                           rg[i * 2 + 1] = toByte(0.5f * (n[1] * inv + 1.0f));
                         }
                         stb_compress_bc5_block(out, rg);
                       });
                     });
}

}  // namespace terralod
