#include "terralod/vegetation/terrain_shear.h"

#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>

#include "terralod/vegetation/ldi_warp.h"

namespace terralod::veg {
namespace {

const TileOnTerrain kTile{{100, 200}, 4, {10, 12, 15, 11}};  // SW, SE, NE, NW

glm::vec3 apply(const glm::mat4& m, glm::vec3 p) {
  return glm::vec3(m * glm::vec4(p, 1));
}

TEST(TerrainShear, EachHalfLiesOnItsTerrainTriangleAndTheHalvesMeetOnTheDiagonal) {
  const glm::mat4 se = halfShear(kTile, TileHalf::kSouthEast),
                  nw = halfShear(kTile, TileHalf::kNorthWest);
  EXPECT_EQ(apply(se, {0, 0, 0}), glm::vec3(100, 200, 10));
  EXPECT_EQ(apply(se, {4, 0, 0}), glm::vec3(104, 200, 12));
  EXPECT_EQ(apply(se, {4, 4, 0}), glm::vec3(104, 204, 15));
  EXPECT_EQ(apply(nw, {0, 4, 0}), glm::vec3(100, 204, 11));
  EXPECT_EQ(apply(nw, {4, 4, 0}), glm::vec3(104, 204, 15));
  for (float t : {0.0f, 0.3f, 1.7f, 4.0f}) {  // the diagonal, at any height above the ground
    const glm::vec3 p(t, t, 0.8f);
    EXPECT_NEAR(glm::distance(apply(se, p), apply(nw, p)), 0.0f, 1e-5f) << t;
  }
  // Heights above the ground stay heights above the terrain: up stays up.
  EXPECT_NEAR(apply(se, {3, 1, 2}).z - apply(se, {3, 1, 0}).z, 2.0f, 1e-5f);
}

TEST(TerrainShear, TheHalfAcrossTheDiagonalFromTheEyeIsDrawnFirst) {
  EXPECT_EQ(farHalf(kTile, {110, 190, 20}), TileHalf::kNorthWest);  // eye to the south-east
  EXPECT_EQ(farHalf(kTile, {90, 215, 20}), TileHalf::kSouthEast);   // eye to the north-west
}

TEST(TerrainShear, AWarpOfOneHalfDrawsOnlyThePixelsOverIt) {
  Ldi ldi;
  ldi.camera.width = ldi.camera.height = 8;
  ldi.camera.pixelSize = 0.5f;
  ldi.camera.direction = {0, 0, -1};
  ldi.camera.depthMin = -3;
  ldi.camera.depthMax = 0.01f;
  ldi.layerCounts.assign(64, 1);
  for (int i = 0; i < 64; ++i)
    ldi.pixels.push_back(
        DepthPixel::make(0xff0000ffu, kLdiMaxDepth / 2, encodeSplatNormal({0, 0, 1})));
  const glm::vec3 eye(2, 2, 50);
  const glm::mat4 view = glm::ortho(-2.0f, 2.0f, -2.0f, 2.0f, 0.0f, 100.0f) *
                         glm::lookAt(eye, glm::vec3(2, 2, 0), glm::vec3(0, 1, 0));
  int drawn[2] = {0, 0};
  for (TileHalf half : {TileHalf::kSouthEast, TileHalf::kNorthWest}) {
    WarpOptions o;
    o.onlyHalf = half;
    WarpTarget t(8, 8);
    warpLdi(ldi, view, eye, t, o);
    for (int y = 0; y < 8; ++y)
      for (int x = 0; x < 8; ++x)
        if (t.rgba[4 * (y * 8 + x) + 3] > 0) {
          ++drawn[int(half)];
          const int column = x, row = 7 - y;  // the LDI pixel under target pixel (x, y)
          EXPECT_EQ(halfOf(column + 0.5f, row + 0.5f), half) << x << "," << y;
        }
  }
  EXPECT_EQ(drawn[0] + drawn[1], 64);
}

}  // namespace
}  // namespace terralod::veg
