#include "terralod/materials/detail_texture.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>

namespace terralod {
namespace {

const std::vector<Material> kMaterials = {
    {0, "water", {58, 96, 128}},           {1, "grass", {96, 124, 60}},
    {2, "soil", {128, 104, 76}},           {3, "rock", {112, 108, 104}},
    {4, "snow", {236, 240, 244}},          {5, "basalt", {40, 40, 44}},
    {6, "Red Sandstone", {170, 120, 105}}, {7, "class 7", {31, 119, 180}},
    {8, "snow", {255, 255, 255}},          {9, "rock", {2, 3, 250}},
};

// Mean absolute difference between horizontally (or vertically) adjacent pixels, over the pairs
// inside the texture and over the pairs across its wrap seam.
struct Gradients {
  double interior = 0, seam = 0;
};
Gradients gradients(const DetailTexture& t, bool vertical) {
  const int n = t.size;
  auto at = [&](int x, int y, int c) { return double(t.rgb[(size_t(y) * n + x) * 3 + c]); };
  double interior = 0, seam = 0;
  for (int a = 0; a < n; ++a)
    for (int c = 0; c < 3; ++c) {
      for (int b = 0; b + 1 < n; ++b)
        interior += vertical ? std::abs(at(a, b + 1, c) - at(a, b, c))
                             : std::abs(at(b + 1, a, c) - at(b, a, c));
      seam += vertical ? std::abs(at(a, 0, c) - at(a, n - 1, c))
                       : std::abs(at(0, a, c) - at(n - 1, a, c));
    }
  return {interior / (double(n) * (n - 1) * 3), seam / (double(n) * 3)};
}

TEST(DetailTexture, MeanColourIsTheMaterialsWithin2) {
  for (const Material& m : kMaterials)
    for (int size : {64, 256}) {
      const DetailTexture t = makeDetailTexture(m, size);
      ASSERT_EQ(t.size, size);
      ASSERT_EQ(t.rgb.size(), size_t(size) * size * 3);
      for (int c = 0; c < 3; ++c) {
        double sum = 0;
        for (size_t i = 0; i < size_t(size) * size; ++i) sum += t.rgb[i * 3 + c];
        EXPECT_NEAR(sum / (double(size) * size), m.color[c], 2.0)
            << m.name << " channel " << c << " size " << size;
      }
    }
}

TEST(DetailTexture, TilesSeamlesslyBothWays) {
  for (const Material& m : kMaterials)
    for (bool vertical : {false, true}) {
      const Gradients g = gradients(makeDetailTexture(m, 256), vertical);
      // Across the seam the texture changes no more than between any two neighbours inside.
      EXPECT_LE(g.seam, 1.3 * g.interior + 0.5)
          << m.name << (vertical ? " vertical" : " horizontal") << ": seam " << g.seam
          << ", interior " << g.interior;
    }
}

TEST(DetailTexture, TheSeamCheckCatchesATextureThatDoesNotTile) {
  // The south-west quarter of a 512² texture is not periodic at 256: its seams show.
  for (const char* name : {"water", "soil", "rock", "snow"}) {
    const DetailTexture big = makeDetailTexture({0, name, {128, 128, 128}}, 512);
    DetailTexture crop{256, std::vector<uint8_t>(256 * 256 * 3)};
    for (int y = 0; y < 256; ++y)
      std::copy_n(big.rgb.begin() + ptrdiff_t(y) * 512 * 3, 256 * 3,
                  crop.rgb.begin() + ptrdiff_t(y) * 256 * 3);
    for (bool vertical : {false, true}) {
      const Gradients g = gradients(crop, vertical);
      EXPECT_GT(g.seam, 1.3 * g.interior + 0.5) << name << (vertical ? " vertical" : "");
    }
  }
}

TEST(DetailTexture, CharacterFollowsTheMaterial) {
  auto contrast = [](const char* name) {
    const DetailTexture t = makeDetailTexture({0, name, {128, 128, 128}}, 256);
    double sum = 0, sum2 = 0;
    for (size_t i = 0; i < t.rgb.size(); i += 3)
      sum += t.rgb[i], sum2 += double(t.rgb[i]) * t.rgb[i];
    const double n = double(t.rgb.size() / 3), mean = sum / n;
    return std::sqrt(sum2 / n - mean * mean);
  };
  const double rock = contrast("rock"), snow = contrast("snow"), grass = contrast("grass");
  std::printf("standard deviation: rock %.1f, grass %.1f, snow %.1f, soil %.1f, water %.1f\n", rock,
              grass, snow, contrast("soil"), contrast("water"));
  EXPECT_GT(rock, 2 * grass);
  EXPECT_GT(grass, 2 * snow);
  EXPECT_GT(snow, 0.5);
  // Unknown names: generic noise seeded by the id, so two ids differ.
  EXPECT_NE(makeDetailTexture({1, "thing", {90, 90, 90}}, 64).rgb,
            makeDetailTexture({2, "thing", {90, 90, 90}}, 64).rgb);
}

TEST(DetailTexture, DeterministicAndFast) {
  for (const Material& m : kMaterials)
    EXPECT_EQ(makeDetailTexture(m, 128).rgb, makeDetailTexture(m, 128).rgb) << m.name;
  const auto start = std::chrono::steady_clock::now();
  for (int i = 0; i < 5; ++i) (void)makeDetailTexture(kMaterials[size_t(i)], 256);
  const double ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count() /
      5;
  std::printf("makeDetailTexture 256x256: %.2f ms per texture\n", ms);
  EXPECT_LT(ms, 100.0);
}

}  // namespace
}  // namespace terralod
