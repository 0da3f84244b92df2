// VIPM tilesets through EGL: the VIPM chunk kind draws a small hand-made tileset
// (vipm_test_tileset.h) with texture splatting, flanges and geomorphing.

#include <gtest/gtest.h>

#include <cstdlib>

#include "headless_scene.h"
#include "temp_dir.h"
#include "terralod/render/framebuffer.h"
#include "terralod/render/gl_context.h"
#include "terralod/render/image.h"
#include "terralod/render/terrain_scene.h"
#include "vipm_test_tileset.h"

namespace terralod {
namespace {

class VipmRender : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    sDir = new test::TempDir;
    ASSERT_EQ(test::writeVipmTestTileset(sDir->file("crater.tlod")), "");
    if (const char* dir = std::getenv("TERRALOD_VIPM_TEST_IMAGES")) {
      ASSERT_EQ(test::writeVipmTestTileset(std::string(dir) + "/crater.tlod"), "");
    }
  }
  static void TearDownTestSuite() { delete sDir; }

  void SetUp() override {
    test::HeadlessScene opened;
    ASSERT_EQ(test::openHeadlessScene(sDir->file("crater.tlod"), test::Frames::kComplete, opened),
              "");
    mContext = std::move(opened.context);
    mScene = std::move(opened.scene);
  }
  void TearDown() override {
    mScene.reset();
    mContext.reset();
  }

  struct Frame {
    Image image;
    FrameStats stats;
  };
  Frame draw(const Camera& camera, SelectionOptions selection = {}, TerrainStyle style = {},
             const char* name = nullptr) {
    auto target = Framebuffer::create(camera.width, camera.height).value();
    target.bind();
    style.sky = false;  // background pixels keep exactly the background colour
    style.haze = 0.0;
    auto stats = mScene->renderFrame(makeView(camera).value(), selection, style);
    EXPECT_TRUE(stats.ok()) << stats.error().message;
    Frame f{target.readPixels(), stats.ok() ? *stats : FrameStats{}};
    if (const char* dir = std::getenv("TERRALOD_VIPM_TEST_IMAGES"); dir && name) {
      EXPECT_TRUE(writePng(f.image, std::string(dir) + "/" + name + ".png").ok());
    }
    return f;
  }
  static uint64_t backgroundPixels(const Image& image, const TerrainStyle& style = {}) {
    uint64_t n = 0;
    for (size_t i = 0; i < image.rgba.size(); i += 4)
      n += image.rgba[i] == style.background[0] && image.rgba[i + 1] == style.background[1] &&
           image.rgba[i + 2] == style.background[2];
    return n;
  }

  // Straight down (almost) from 800 m over the middle of the window: only terrain in view.
  static Camera downCamera() {
    Camera c;
    c.eye = {1290, 1744, 2900};
    c.target = {1290, 1745, 1800};
    c.width = 320;
    c.height = 240;
    return c;
  }
  // Low over the southern part, looking north across the window.
  static Camera lowCamera() {
    Camera c;
    c.eye = {1290, -300, 2300};
    c.target = {1290, 2500, 1900};
    c.width = 320;
    c.height = 240;
    return c;
  }

  // Background pixels below terrain in their column: holes (with the eye over the data and
  // the image's bottom row on terrain, nothing else lets the background through there).
  static uint64_t holes(const Image& image, const TerrainStyle& style = {}) {
    uint64_t n = 0;
    for (int x = 0; x < image.width; ++x) {
      bool terrain = false;
      for (int y = 0; y < image.height; ++y) {
        const auto p = image.pixel(x, y);
        const bool background = p[0] == style.background[0] && p[1] == style.background[1] &&
                                p[2] == style.background[2];
        terrain = terrain || !background;
        n += terrain && background;
      }
    }
    return n;
  }

  static inline test::TempDir* sDir = nullptr;
  std::unique_ptr<GlContext> mContext;
  std::unique_ptr<TerrainScene> mScene;
};

TEST_F(VipmRender, CoversTheGroundWithoutHoles) {
  const Frame f = draw(downCamera(), {}, {}, "down");
  EXPECT_EQ(f.stats.draw.chunks, 4u);
  EXPECT_EQ(f.stats.draw.missing, 0u);
  EXPECT_EQ(backgroundPixels(f.image), 0u);
}

TEST_F(VipmRender, FlangesCloseTheCracksBetweenLevels) {
  // Low over the window's south-west leaf, looking north-east across the others: the leaves
  // are at different levels, and without flanges the sky shows through cracks between them.
  Camera c;
  c.eye = {200, 200, 2150};
  c.target = {1000, 1700, 1850};
  c.width = 320;
  c.height = 240;
  TerrainStyle noSkirts;
  noSkirts.skirts = false;
  const Frame with = draw(c, {}, {}, "cracks-flanges");
  const Frame without = draw(c, {}, noSkirts, "cracks-none");
  EXPECT_EQ(holes(with.image), 0u);
  EXPECT_GT(holes(without.image), 20u);
  EXPECT_GT(with.stats.draw.triangles, without.stats.draw.triangles);
}

TEST_F(VipmRender, SplatsEveryMaterialsColour) {
  // Water (#2050a0) by the lake, grass (#40a030) and rock (#a09080) above it: each material's
  // detail texture averages its colour, so its pixels lean towards that colour.
  const Frame f = draw(lowCamera(), {}, {}, "low");
  uint64_t blue = 0, green = 0, warm = 0, pixels = 0;
  for (size_t i = 0; i < f.image.rgba.size(); i += 4) {
    const int r = f.image.rgba[i], g = f.image.rgba[i + 1], b = f.image.rgba[i + 2];
    if (r == 0x9C && g == 0xC3 && b == 0xE6) continue;  // background
    ++pixels;
    blue += b > g + 20 && b > r + 40;
    green += g > r + 30 && g > b + 30;
    warm += r > g && g > b && r < g + 40;
  }
  ASSERT_GT(pixels, 10000u);
  EXPECT_GT(blue, pixels / 200);
  EXPECT_GT(green, pixels / 10);
  EXPECT_GT(warm, pixels / 20);
}

TEST_F(VipmRender, FartherChunksDrawFewerTriangles) {
  Camera far;
  far.eye = {-3000, -4000, 9000};
  far.target = {1290, 1744, 1900};
  far.width = 320;
  far.height = 240;
  const Frame f = draw(far, {}, {}, "far");
  const Frame d = draw(downCamera(), {}, {}, "down");
  EXPECT_EQ(f.stats.draw.chunks, 4u);
  EXPECT_LT(f.stats.draw.triangles * 3, d.stats.draw.triangles);
}

TEST_F(VipmRender, GeomorphingOffShowsOtherGeometry) {
  // With morphing the vertices of collapses within kMorphSpan of the allowed error are
  // between their levels; without it (--no-morph) they sit on one.
  SelectionOptions noMorph;
  noMorph.morph = false;
  const Frame morphed = draw(lowCamera(), {}, {}, "low");
  const Frame popped = draw(lowCamera(), noMorph, {}, "low-nomorph");
  uint64_t differ = 0;
  for (size_t i = 0; i < morphed.image.rgba.size(); ++i)
    differ += morphed.image.rgba[i] != popped.image.rgba[i];
  EXPECT_GT(differ, 100u);
}

}  // namespace
}  // namespace terralod
