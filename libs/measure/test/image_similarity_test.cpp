#include "terralod/measure/image_similarity.h"

#include <gtest/gtest.h>

#include <cmath>

namespace terralod {
namespace {

// Stripes 6 pixels wide (so they survive the comparison's 3×3 averaging at this size), grey
// levels lo and hi.
Image stripes(int width, int height, uint8_t lo, uint8_t hi, int shift = 0) {
  Image image{width, height, std::vector<uint8_t>(size_t(width) * height * 4, 255)};
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const uint8_t v = ((x + shift) / 6) % 2 ? hi : lo;
      uint8_t* p = &image.rgba[(size_t(y) * width + x) * 4];
      p[0] = p[1] = p[2] = v;
    }
  return image;
}

TEST(ImageSimilarity, IsOneForTheSamePictureAndFallsWithWhatChangesItsStructure) {
  const Image a = stripes(1024, 768, 40, 200);
  EXPECT_EQ(similarityScale(1024, 768), 3);
  EXPECT_NEAR(structuralSimilarity(a, a).mean, 1.0, 1e-12);
  // Brighter by a little: structure kept, the luminance term alone moves.
  EXPECT_GT(structuralSimilarity(a, stripes(1024, 768, 50, 210)).mean, 0.95);
  // Half a period along: the stripes' structure is opposite.
  EXPECT_LT(structuralSimilarity(a, stripes(1024, 768, 40, 200, 6)).mean, 0.0);
  // Flat grey of the same mean: no structure at all.
  EXPECT_LT(structuralSimilarity(a, stripes(1024, 768, 120, 120)).mean, 0.1);
}

TEST(ImageSimilarity, CountsOnlyWhereTheMaskIsSet) {
  const Image a = stripes(768, 768, 40, 200);
  Image b = a;
  // The lower half flat; the mask keeps the upper half.
  for (size_t i = b.rgba.size() / 2; i < b.rgba.size(); i += 4)
    b.rgba[i] = b.rgba[i + 1] = b.rgba[i + 2] = 120;
  std::vector<uint8_t> upper(size_t(768) * 768, 0);
  std::fill(upper.begin(), upper.begin() + ptrdiff_t(upper.size() / 2) - 768 * 48, 1);
  const Similarity masked = structuralSimilarity(a, b, upper);
  EXPECT_NEAR(masked.mean, 1.0, 1e-9);
  EXPECT_LT(masked.pixels, size_t(256) * 128);
  EXPECT_LT(structuralSimilarity(a, b).mean, 0.7);
}

}  // namespace
}  // namespace terralod
