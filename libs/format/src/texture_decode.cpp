#include "terralod/format/texture_decode.h"

#include <array>

namespace terralod {
namespace {

// RGB565 to 8 bits per channel by bit replication (0 -> 0, 31 -> 255, 63 -> 255).
std::array<int, 3> expand565(int c) {
  const int r = (c >> 11) & 31, g = (c >> 5) & 63, b = c & 31;
  return {(r << 3) | (r >> 2), (g << 2) | (g >> 4), (b << 3) | (b >> 2)};
}

}  // namespace

std::vector<uint8_t> decodeBc1Rgb(std::span<const uint8_t> blocks, uint32_t size) {
  if (size == 0 || blocks.size() != mipBytes(TextureEncoding::kBc1, size, 0)) return {};
  const uint32_t across = (size + 3) / 4;
  std::vector<uint8_t> out(size_t(size) * size * 3);
  for (uint32_t by = 0; by < across; ++by)
    for (uint32_t bx = 0; bx < across; ++bx) {
      const uint8_t* b = blocks.data() + (size_t(by) * across + bx) * 8;
      const int c0 = b[0] | b[1] << 8, c1 = b[2] | b[3] << 8;
      std::array<std::array<int, 3>, 4> palette = {expand565(c0), expand565(c1)};
      for (size_t ch = 0; ch < 3; ++ch) {
        const int p0 = palette[0][ch], p1 = palette[1][ch];
        palette[2][ch] = c0 > c1 ? (2 * p0 + p1) / 3 : (p0 + p1) / 2;
        palette[3][ch] = c0 > c1 ? (p0 + 2 * p1) / 3 : 0;
      }
      const uint32_t bits =
          uint32_t(b[4]) | uint32_t(b[5]) << 8 | uint32_t(b[6]) << 16 | uint32_t(b[7]) << 24;
      for (uint32_t r = 0; r < 4; ++r)
        for (uint32_t c = 0; c < 4; ++c) {
          const uint32_t x = bx * 4 + c, y = by * 4 + r;
          if (x >= size || y >= size) continue;
          const auto& colour = palette[(bits >> (2 * (r * 4 + c))) & 3];
          uint8_t* texel = out.data() + (size_t(y) * size + x) * 3;
          for (size_t ch = 0; ch < 3; ++ch) texel[ch] = uint8_t(colour[ch]);
        }
    }
  return out;
}

namespace {

// The RGTC channels of blocks of `blockBytes` bytes (BC4: 8, one channel; BC5: 16, red's 8
// bytes then green's), each decoded as RGTC defines it.
std::vector<uint8_t> decodeRgtc(std::span<const uint8_t> blocks, uint32_t size, uint32_t channels) {
  const uint32_t across = (size + 3) / 4;
  std::vector<uint8_t> out(size_t(size) * size * channels);
  for (uint32_t by = 0; by < across; ++by)
    for (uint32_t bx = 0; bx < across; ++bx)
      for (uint32_t ch = 0; ch < channels; ++ch) {
        const uint8_t* b = blocks.data() + ((size_t(by) * across + bx) * channels + ch) * 8;
        const int r0 = b[0], r1 = b[1];
        std::array<int, 8> palette{r0, r1};
        for (int k = 1; k < 7; ++k)  // rounded to the nearest, as GPUs return 8-bit values
          palette[size_t(k + 1)] = r0 > r1  ? ((7 - k) * r0 + k * r1 + 3) / 7
                                   : k < 5  ? ((5 - k) * r0 + k * r1 + 2) / 5
                                   : k == 5 ? 0
                                            : 255;
        uint64_t bits = 0;
        for (int k = 0; k < 6; ++k) bits |= uint64_t(b[2 + k]) << (8 * k);
        for (uint32_t r = 0; r < 4; ++r)
          for (uint32_t c = 0; c < 4; ++c) {
            const uint32_t x = bx * 4 + c, y = by * 4 + r;
            if (x >= size || y >= size) continue;
            out[(size_t(y) * size + x) * channels + ch] =
                uint8_t(palette[(bits >> (3 * (r * 4 + c))) & 7]);
          }
      }
  return out;
}

}  // namespace

std::vector<uint8_t> decodeBc5Rg(std::span<const uint8_t> blocks, uint32_t size) {
  if (size == 0 || blocks.size() != mipBytes(TextureEncoding::kBc5, size, 0)) return {};
  return decodeRgtc(blocks, size, 2);
}

std::vector<uint8_t> decodeBc4R(std::span<const uint8_t> blocks, uint32_t size) {
  if (size == 0 || blocks.size() != mipBytes(TextureEncoding::kBc4, size, 0)) return {};
  return decodeRgtc(blocks, size, 1);
}

}  // namespace terralod
