#pragma once
// Reference decoders for the GPU block formats texture blobs store (docs/format.md, "Version
// 2: textures"): BC1 (colour, 8-byte blocks) and BC5 (two BC4 channels, 16-byte blocks).
// Written from the format specifications, independently of the encoder, for tests to check
// what a GPU would sample.
//
// A mip level of `size` texels is ceil(size / 4)^2 blocks, row-major from the south-west:
// block row 0 holds texel rows 0..3 and texel row 0 is the southern one. Within a block texel
// (column c, row r) is index r * 4 + c.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace terralod::test {

/// A BC4 block (8 bytes) decoded to 16 values 0..255, texel i = row * 4 + column.
inline std::array<int, 16> decodeBc4Block(const uint8_t* b) {
  const int e0 = b[0], e1 = b[1];
  int palette[8] = {e0, e1};
  if (e0 > e1) {
    for (int i = 2; i < 8; ++i) palette[i] = ((8 - i) * e0 + (i - 1) * e1) / 7;
  } else {
    for (int i = 2; i < 6; ++i) palette[i] = ((6 - i) * e0 + (i - 1) * e1) / 5;
    palette[6] = 0;
    palette[7] = 255;
  }
  uint64_t bits = 0;
  for (int i = 0; i < 6; ++i) bits |= uint64_t(b[2 + i]) << (8 * i);
  std::array<int, 16> out;
  for (int i = 0; i < 16; ++i) out[size_t(i)] = palette[(bits >> (3 * i)) & 7];
  return out;
}

/// A BC1 block (8 bytes) decoded to 16 RGB triples 0..255, texel i = row * 4 + column. Both
/// modes: c0 > c1 four colours, otherwise three and black (the "transparent" index decodes
/// to black, alpha being ignored for RGB BC1).
inline std::array<std::array<int, 3>, 16> decodeBc1Block(const uint8_t* b) {
  const int c0 = b[0] | (b[1] << 8), c1 = b[2] | (b[3] << 8);
  auto expand = [](int c) {
    const int r = (c >> 11) & 31, g = (c >> 5) & 63, bl = c & 31;
    return std::array<int, 3>{(r << 3) | (r >> 2), (g << 2) | (g >> 4), (bl << 3) | (bl >> 2)};
  };
  std::array<std::array<int, 3>, 4> p = {expand(c0), expand(c1), {}, {}};
  for (int ch = 0; ch < 3; ++ch) {
    if (c0 > c1) {
      p[2][size_t(ch)] = (2 * p[0][size_t(ch)] + p[1][size_t(ch)]) / 3;
      p[3][size_t(ch)] = (p[0][size_t(ch)] + 2 * p[1][size_t(ch)]) / 3;
    } else {
      p[2][size_t(ch)] = (p[0][size_t(ch)] + p[1][size_t(ch)]) / 2;
      p[3][size_t(ch)] = 0;
    }
  }
  const uint32_t bits = b[4] | (b[5] << 8) | (b[6] << 16) | (uint32_t(b[7]) << 24);
  std::array<std::array<int, 3>, 16> out;
  for (int i = 0; i < 16; ++i) out[size_t(i)] = p[(bits >> (2 * i)) & 3];
  return out;
}

/// Bytes of one mip level of `size` texels in whole 4x4 blocks of `blockBytes`.
inline size_t bcLevelBytes(uint32_t size, size_t blockBytes) {
  const size_t blocks = (size_t(size) + 3) / 4;
  return blocks * blocks * blockBytes;
}

/// The block holding texel (x, y) of a mip level of `size` texels.
inline const uint8_t* bcBlockOf(std::span<const uint8_t> mip, uint32_t size, uint32_t x, uint32_t y,
                                size_t blockBytes) {
  const size_t blocks = (size_t(size) + 3) / 4;
  return mip.data() + (size_t(y / 4) * blocks + x / 4) * blockBytes;
}

/// A BC1 mip level of `size` texels decoded to RGB8, row-major, south row first:
/// texel (x, y) at [(y * size + x) * 3]. Empty when `mip` is not exactly the level's bytes.
inline std::vector<uint8_t> decodeBc1Layer(std::span<const uint8_t> mip, uint32_t size) {
  if (size == 0 || mip.size() != bcLevelBytes(size, 8)) return {};
  std::vector<uint8_t> out(size_t(size) * size * 3);
  const uint32_t blocks = (size + 3) / 4;
  for (uint32_t by = 0; by < blocks; ++by)
    for (uint32_t bx = 0; bx < blocks; ++bx) {
      const auto texels = decodeBc1Block(mip.data() + (size_t(by) * blocks + bx) * 8);
      for (uint32_t r = 0; r < 4; ++r)
        for (uint32_t c = 0; c < 4; ++c) {
          const uint32_t x = bx * 4 + c, y = by * 4 + r;
          if (x >= size || y >= size) continue;
          for (size_t ch = 0; ch < 3; ++ch)
            out[(size_t(y) * size + x) * 3 + ch] = uint8_t(texels[r * 4 + c][ch]);
        }
    }
  return out;
}

/// A BC5 mip level of `size` texels decoded to RG8 (red from the first BC4 half of each
/// block, green from the second), row-major, south row first: texel (x, y) at
/// [(y * size + x) * 2]. Empty when `mip` is not exactly the level's bytes.
inline std::vector<uint8_t> decodeBc5Layer(std::span<const uint8_t> mip, uint32_t size) {
  if (size == 0 || mip.size() != bcLevelBytes(size, 16)) return {};
  std::vector<uint8_t> out(size_t(size) * size * 2);
  const uint32_t blocks = (size + 3) / 4;
  for (uint32_t by = 0; by < blocks; ++by)
    for (uint32_t bx = 0; bx < blocks; ++bx) {
      const uint8_t* block = mip.data() + (size_t(by) * blocks + bx) * 16;
      const auto red = decodeBc4Block(block), green = decodeBc4Block(block + 8);
      for (uint32_t r = 0; r < 4; ++r)
        for (uint32_t c = 0; c < 4; ++c) {
          const uint32_t x = bx * 4 + c, y = by * 4 + r;
          if (x >= size || y >= size) continue;
          out[(size_t(y) * size + x) * 2] = uint8_t(red[r * 4 + c]);
          out[(size_t(y) * size + x) * 2 + 1] = uint8_t(green[r * 4 + c]);
        }
    }
  return out;
}

/// The unit normal a normal-map texel stores: channels v = (n + 1) / 2 for east and north,
/// up = sqrt(1 - x² - y²).
inline std::array<double, 3> normalFromRg8(uint8_t red, uint8_t green) {
  const double nx = 2.0 * red / 255.0 - 1.0, ny = 2.0 * green / 255.0 - 1.0;
  return {nx, ny, std::sqrt(std::max(0.0, 1 - nx * nx - ny * ny))};
}

}  // namespace terralod::test
