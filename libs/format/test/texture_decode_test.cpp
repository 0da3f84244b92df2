#include "terralod/format/texture_decode.h"

#include <gtest/gtest.h>

#include <random>

#include "bc_decode.h"  // tests/support: the tests' own reference decoder

namespace terralod {
namespace {

TEST(DecodeBc1Rgb, FourColourBlockInterpolatesBetweenItsEndPoints) {
  // c0 = pure red (0xF800) > c1 = pure blue (0x001F): four colours, thirds between them.
  // Indices 0, 1, 2, 3 along the first row (south), then all 0, 1, 2, 3 in the next rows.
  const uint8_t block[8] = {0x00, 0xF8, 0x1F, 0x00, 0b11100100, 0x00, 0x55, 0xFF};
  const std::vector<uint8_t> rgb = decodeBc1Rgb(block, 4);
  ASSERT_EQ(rgb.size(), 4u * 4 * 3);
  auto texel = [&](int x, int y) {
    const uint8_t* p = &rgb[size_t(y * 4 + x) * 3];
    return std::array<int, 3>{p[0], p[1], p[2]};
  };
  EXPECT_EQ(texel(0, 0), (std::array<int, 3>{255, 0, 0}));
  EXPECT_EQ(texel(1, 0), (std::array<int, 3>{0, 0, 255}));
  EXPECT_EQ(texel(2, 0), (std::array<int, 3>{170, 0, 85}));
  EXPECT_EQ(texel(3, 0), (std::array<int, 3>{85, 0, 170}));
  EXPECT_EQ(texel(3, 1), (std::array<int, 3>{255, 0, 0}));
  EXPECT_EQ(texel(0, 2), (std::array<int, 3>{0, 0, 255}));
  EXPECT_EQ(texel(0, 3), (std::array<int, 3>{85, 0, 170}));
}

TEST(DecodeBc1Rgb, ThreeColourBlockHasMidpointAndBlack) {
  // c0 = blue <= c1 = white: index 2 is the midpoint, index 3 black.
  const uint8_t block[8] = {0x1F, 0x00, 0xFF, 0xFF, 0b11100100, 0, 0, 0};
  const std::vector<uint8_t> rgb = decodeBc1Rgb(block, 4);
  ASSERT_EQ(rgb.size(), 48u);
  EXPECT_EQ((std::vector<uint8_t>(rgb.begin(), rgb.begin() + 12)),
            (std::vector<uint8_t>{0, 0, 255, 255, 255, 255, 127, 127, 255, 0, 0, 0}));
}

TEST(DecodeBc1Rgb, AgreesWithTheTestsReferenceDecoderOnRandomTiles) {
  std::mt19937 rng(7);
  for (uint32_t size : {1u, 2u, 3u, 4u, 5u, 17u, 33u}) {
    SCOPED_TRACE(size);
    std::vector<uint8_t> blocks(mipBytes(TextureEncoding::kBc1, size, 0));
    for (uint8_t& b : blocks) b = uint8_t(rng());
    const std::vector<uint8_t> rgb = decodeBc1Rgb(blocks, size);
    EXPECT_EQ(rgb.size(), size_t(size) * size * 3);
    EXPECT_EQ(rgb, test::decodeBc1Layer(blocks, size));
  }
}

TEST(DecodeBc1Rgb, WrongByteCountDecodesToNothing) {
  const std::vector<uint8_t> blocks(32, 0);  // 2x2 blocks: 5 to 8 texels a side
  EXPECT_TRUE(decodeBc1Rgb(blocks, 4).empty());
  EXPECT_TRUE(decodeBc1Rgb(blocks, 9).empty());
  EXPECT_TRUE(decodeBc1Rgb(blocks, 0).empty());
  EXPECT_EQ(decodeBc1Rgb(blocks, 5).size(), 75u);
}

TEST(DecodeBc5Rg, EightAndSixValueModesPerChannel) {
  // Red: 200 > 100, eight values; indices 0, 1, 2, 7 along the south row. Green: 100 <= 200,
  // six values then 0 and 255; indices 6, 7, 2, 5 along the south row.
  const uint8_t block[16] = {200, 100, 0b10001000, 0b00001110, 0, 0, 0, 0,
                             100, 200, 0b10111110, 0b00001010, 0, 0, 0, 0};
  const std::vector<uint8_t> rg = decodeBc5Rg(block, 4);
  ASSERT_EQ(rg.size(), 4u * 4 * 2);
  // Rounded to the nearest 8-bit value of the palette (GPUs interpolate in floating point).
  EXPECT_EQ((std::vector<int>{rg[0], rg[2], rg[4], rg[6]}), (std::vector<int>{200, 100, 186, 114}));
  EXPECT_EQ((std::vector<int>{rg[1], rg[3], rg[5], rg[7]}), (std::vector<int>{0, 255, 120, 180}));
}

TEST(DecodeBc5Rg, AgreesWithTheTestsReferenceDecoderWithinRounding) {
  std::mt19937 rng(11);
  for (uint32_t size : {1u, 3u, 4u, 5u, 65u}) {
    SCOPED_TRACE(size);
    std::vector<uint8_t> blocks(mipBytes(TextureEncoding::kBc5, size, 0));
    for (uint8_t& b : blocks) b = uint8_t(rng());
    const std::vector<uint8_t> rg = decodeBc5Rg(blocks, size);
    const std::vector<uint8_t> reference = test::decodeBc5Layer(blocks, size);  // truncates
    ASSERT_EQ(rg.size(), reference.size());
    for (size_t i = 0; i < rg.size(); ++i) EXPECT_NEAR(rg[i], reference[i], 1) << i;
  }
  EXPECT_TRUE(decodeBc5Rg(std::vector<uint8_t>(16), 5).empty());
}

TEST(DecodeBc4R, IsBc5sRedChannel) {
  std::mt19937 rng(12);
  for (uint32_t size : {1u, 4u, 33u}) {
    SCOPED_TRACE(size);
    std::vector<uint8_t> bc4(mipBytes(TextureEncoding::kBc4, size, 0));
    for (uint8_t& b : bc4) b = uint8_t(rng());
    // The same blocks as BC5's red halves (green all zero).
    std::vector<uint8_t> bc5;
    for (size_t b = 0; b < bc4.size(); b += 8) {
      bc5.insert(bc5.end(), bc4.begin() + ptrdiff_t(b), bc4.begin() + ptrdiff_t(b + 8));
      bc5.insert(bc5.end(), 8, 0);
    }
    const std::vector<uint8_t> r = decodeBc4R(bc4, size);
    const std::vector<uint8_t> rg = decodeBc5Rg(bc5, size);
    ASSERT_EQ(r.size(), size_t(size) * size);
    for (size_t i = 0; i < r.size(); ++i) EXPECT_EQ(r[i], rg[i * 2]) << i;
  }
  EXPECT_TRUE(decodeBc4R(std::vector<uint8_t>(16), 5).empty());
}

}  // namespace
}  // namespace terralod
