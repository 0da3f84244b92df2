#include "terralod/vegetation/ldi_warp.h"

#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>

namespace terralod::veg {
namespace {

// A top-down LDI over [0, 0.1·n]², the image plane 2 m up.
LdiCamera topDown(uint32_t n) {
  LdiCamera c;
  c.width = c.height = n;
  c.pixelSize = 0.1f;
  c.direction = {0, 0, -1};
  c.depthMin = -2;
  c.depthMax = 0.01f;
  return c;
}

uint32_t quantized(const LdiCamera& c, float depth) {
  return uint32_t(std::lround((depth - c.depthMin) / (c.depthMax - c.depthMin) * kLdiMaxDepth));
}

uint32_t rgba(uint8_t r, uint8_t g, uint8_t b) {
  return r | g << 8 | b << 16 | 0xffu << 24;
}

const uint32_t kUp = encodeSplatNormal({0, 0, 1});

// Clip space of an orthographic camera that is the LDI's own: target pixel (c, n−1−r) shows
// LDI pixel (c, r).
glm::mat4 ownView(const LdiCamera& c) {
  const float extent = c.pixelSize * float(c.width);
  return glm::ortho(0.0f, extent, 0.0f, extent, c.depthMin, c.depthMax) *
         glm::lookAt(glm::vec3(0, 0, 0), glm::vec3(0, 0, -1), glm::vec3(0, 1, 0));
}

TEST(LdiWarp, SeenFromItsOwnCameraAnLdiIsItsFrontLayers) {
  Ldi ldi;
  ldi.camera = topDown(16);
  for (uint32_t i = 0; i < 16 * 16; ++i) {
    const uint8_t layers = i % 3;  // 0, 1 or 2 layers
    ldi.layerCounts.push_back(layers);
    for (uint8_t k = 0; k < layers; ++k)
      ldi.pixels.push_back(DepthPixel::make(rgba(uint8_t(i), uint8_t(k * 200), 7),
                                            quantized(ldi.camera, 1.5f + 0.2f * k - 2.0f), kUp));
  }
  WarpTarget target(16, 16);
  const WarpStats stats = warpLdi(ldi, ownView(ldi.camera), {0.8f, 0.8f, 50.0f}, target);
  EXPECT_EQ(stats.depthPixels, ldi.pixels.size());
  for (uint32_t r = 0; r < 16; ++r)
    for (uint32_t c = 0; c < 16; ++c) {
      const uint32_t i = r * 16 + c;
      const float* px = &target.rgba[4 * ((15 - r) * 16 + c)];
      if (i % 3 == 0) {
        EXPECT_EQ(px[3], 0.0f) << c << "," << r;
        continue;
      }
      EXPECT_NEAR(px[0] * 255, float(uint8_t(i)), 1e-3) << c << "," << r;
      EXPECT_NEAR(px[1], 0.0f, 1e-6) << "the front layer (green 0) is in front";
    }
}

// A red point 1 m up at column 5 hides a green one on the ground at column 6 from an eye on
// the line through both; the order alone must get that right.
struct Occlusion {
  Ldi ldi;
  glm::vec3 eye, ground;
  Occlusion() {
    ldi.camera = topDown(12);
    ldi.layerCounts.assign(12 * 12, 0);
    ldi.layerCounts[5 * 12 + 5] = 1;
    ldi.layerCounts[5 * 12 + 6] = 1;
    ldi.pixels = {DepthPixel::make(rgba(255, 0, 0), quantized(ldi.camera, -1.0f), kUp),
                  DepthPixel::make(rgba(0, 255, 0), quantized(ldi.camera, 0.0f), kUp)};
    const glm::vec3 high(0.55f, 0.55f, 1.0f);
    ground = glm::vec3(0.65f, 0.55f, 0.0f);
    eye = ground + 6.0f * (high - ground);
  }
  // The colour at the centre of a 33×33 view from the eye at the ground point.
  glm::vec4 centre(WarpOptions o) const {
    o.sizedSplats = false;
    WarpTarget t(33, 33);
    const glm::mat4 m = glm::perspective(glm::radians(30.0f), 1.0f, 0.1f, 100.0f) *
                        glm::lookAt(eye, ground, glm::vec3(0, 1, 0));
    warpLdi(ldi, m, eye, t, o);
    const float* p = &t.rgba[4 * (16 * 33 + 16)];
    return {p[0], p[1], p[2], p[3]};
  }
};

TEST(LdiWarp, TheSheetsAroundTheEpipoleDrawWhatHidesAPointAfterIt) {
  const Occlusion scene;
  WarpOptions mcmillan;
  mcmillan.depthTest = false;
  EXPECT_EQ(scene.centre(mcmillan), glm::vec4(1, 0, 0, 1));  // red: the nearer point
  WarpOptions rowMajor = mcmillan;
  rowMajor.order = WarpOrder::kRowMajor;
  EXPECT_EQ(scene.centre(rowMajor), glm::vec4(0, 1, 0, 1));  // drawn in the wrong order
  WarpOptions depth;
  depth.order = WarpOrder::kRowMajor;
  EXPECT_EQ(scene.centre(depth), glm::vec4(1, 0, 0, 1));  // the depth test mends it
}

TEST(LdiWarp, LayersOfOnePixelAreDrawnAwayFromTheEyeFirst) {
  Ldi ldi;
  ldi.camera = topDown(4);
  ldi.layerCounts.assign(16, 0);
  ldi.layerCounts[5] = 2;  // red 1 m up over green on the ground
  ldi.pixels = {DepthPixel::make(rgba(255, 0, 0), quantized(ldi.camera, -1.0f), kUp),
                DepthPixel::make(rgba(0, 255, 0), quantized(ldi.camera, 0.0f), kUp)};
  WarpOptions o;
  o.depthTest = false;
  o.sizedSplats = false;
  const glm::vec3 at(0.15f, 0.15f, 0.5f);
  for (const auto& [eye, seen] :
       {std::pair{glm::vec3(0.15f, 0.15f, 3.0f), glm::vec4(1, 0, 0, 1)},
        std::pair{glm::vec3(0.15f, 0.15f, -3.0f), glm::vec4(0, 1, 0, 1)}}) {
    WarpTarget t(9, 9);
    const glm::mat4 m = glm::perspective(glm::radians(20.0f), 1.0f, 0.1f, 100.0f) *
                        glm::lookAt(eye, at, glm::vec3(0, 1, 0));
    warpLdi(ldi, m, eye, t, o);
    const float* p = &t.rgba[4 * (4 * 9 + 4)];
    EXPECT_EQ(glm::vec4(p[0], p[1], p[2], p[3]), seen) << "eye z " << eye.z;
  }
}

TEST(LdiWarp, SplatsSizedToTheFootprintLeaveNoHolesWhenMagnified) {
  Ldi ldi;
  ldi.camera = topDown(16);
  ldi.layerCounts.assign(16 * 16, 1);
  for (int i = 0; i < 16 * 16; ++i)
    ldi.pixels.push_back(DepthPixel::make(rgba(200, 100, 50), quantized(ldi.camera, -0.5f), kUp));
  // The same orthographic view, three target pixels to an LDI pixel.
  auto holes = [&](bool sized) {
    WarpOptions o;
    o.sizedSplats = sized;
    WarpTarget t(48, 48);
    warpLdi(ldi, ownView(ldi.camera), {0.8f, 0.8f, 50.0f}, t, o);
    int empty = 0;
    for (int i = 0; i < 48 * 48; ++i) empty += t.rgba[4 * i + 3] == 0;
    return empty;
  };
  EXPECT_EQ(holes(true), 0);
  EXPECT_GT(holes(false), 48 * 48 / 2);
}

}  // namespace
}  // namespace terralod::veg
