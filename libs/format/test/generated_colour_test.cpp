// The shade layer's colour (format version 6): what the shader makes from a shade texel, the
// drawn height and the normal map is the colour a baked build stores, and a texel filtered
// from water and land lies between the two.

#include "terralod/format/generated_colour.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace terralod {
namespace {

float distance(GroundColor a, GroundColor b) {
  return std::max({std::fabs(a.r - b.r), std::fabs(a.g - b.g), std::fabs(a.b - b.b)});
}

TEST(GeneratedColour, ShadeOfLandGivesTheBakedColour) {
  for (float occlusion : {0.6f, 0.7f, 0.85f, 1.0f})
    for (float height : {-20.0f, 150.0f, 1200.0f, 2600.0f, 3100.0f, 4200.0f})
      for (float slope : {0.0f, 0.3f, 0.6f, 0.9f}) {
        const GroundColor g = groundColorBelow(height, slope, 3000.0f);
        const float dim = std::pow(occlusion, 1.0f / 2.2f);
        const GroundColor baked{g.r * dim, g.g * dim, g.b * dim};
        const GroundColor shaded =
            shadedColour(height, slope, 3000.0f, shadeValue(false, occlusion));
        EXPECT_LT(distance(shaded, baked), 1e-5f) << occlusion << " " << height << " " << slope;
      }
}

TEST(GeneratedColour, WaterIsWaterAndMixesWithLand) {
  EXPECT_EQ(shadeValue(true, 0.7f), 0.0f);
  EXPECT_LT(distance(shadedColour(500, 0.8f, 100, 0.0f), kWaterColor), 1e-6f);
  // Land shades never read as water; a texel half water, half open land lies halfway.
  EXPECT_GE(shadeValue(false, 0.0f), kLandShade);
  const GroundColor land = shadedColour(50, 0, 3000, 1.0f);
  const GroundColor half = shadedColour(50, 0, 3000, 0.5f);
  EXPECT_NEAR(half.g, 0.5f * (land.g + kWaterColor.g), 0.08f);
  EXPECT_GT(distance(half, land), 0.05f);
  EXPECT_GT(distance(half, kWaterColor), 0.05f);
}

TEST(GeneratedColour, SnowLineSamplesFollowTheRows) {
  // Rows from 40°N (row 0, south) to 50°N: the snow line falls northwards.
  std::vector<double> latitudes(1001);
  for (size_t i = 0; i < latitudes.size(); ++i) latitudes[i] = 40.0 + 10.0 * double(i) / 1000.0;
  const std::vector<float> s = snowLineSamples(latitudes, 1001);
  ASSERT_EQ(s.size(), kSnowLineSamples);
  EXPECT_NEAR(s.front(), snowLine(40), 0.01);
  EXPECT_NEAR(s.back(), snowLine(50), 0.01);
  EXPECT_NEAR(snowLineAt(s, 0.5), snowLine(45), 2.0);
  EXPECT_EQ(snowLineAt(s, -1.0), s.front());
  EXPECT_EQ(snowLineAt(s, 2.0), s.back());
  // Unknown latitude: the assumed one everywhere.
  for (float v : snowLineSamples({}, 10)) EXPECT_EQ(v, float(snowLine(kUnknownLatitude)));
}

}  // namespace
}  // namespace terralod
