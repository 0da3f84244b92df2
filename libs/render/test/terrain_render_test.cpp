// The terrain renderer on a real DEM through EGL: a golden image, one multi-draw per frame,
// and skirts that close every crack a look-down view could show.

#include <gtest/gtest.h>

#include "image_compare.h"
#include "temp_dir.h"
#include "terralod/build/builder.h"
#include "terralod/render/framebuffer.h"
#include "terralod/render/gl_context.h"
#include "terralod/render/terrain_scene.h"

namespace terralod {
namespace {

using test::TempDir;

constexpr std::array<uint8_t, 3> kMagenta{0xFF, 0x00, 0xFF};

class TerrainRender : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    sDir = new TempDir;
    BuildOptions options;
    options.input = test::testData("crater_lake_0513.bt");
    options.output = sDir->file("crater.tlod");
    options.maxError = 0.5;
    options.textures = false;  // lit from the geometry (textured views: textured_render_test)
    NullProgress progress;
    auto built = buildTileset(options, progress, [](const std::string&) {});
    ASSERT_TRUE(built.ok()) << built.error().message;
  }
  static void TearDownTestSuite() { delete sDir; }

  void SetUp() override {
    auto context = GlContext::createHeadless();
    ASSERT_TRUE(context.ok()) << context.error().message;
    mContext = std::move(context).value();
    auto tileset = TilesetReader::openFile(sDir->file("crater.tlod"));
    ASSERT_TRUE(tileset.ok()) << tileset.error().message;
    SceneOptions options;
    options.complete = true;  // every view fully loaded: fixed pictures
    auto scene = TerrainScene::create(std::move(tileset).value(), options);
    ASSERT_TRUE(scene.ok()) << scene.error().message;
    mScene = std::move(scene).value();
  }
  void TearDown() override {
    mScene.reset();
    mContext.reset();
  }

  Image render(const Camera& camera, const SelectionOptions& selection, const TerrainStyle& style,
               FrameStats* stats = nullptr) {
    auto target = Framebuffer::create(camera.width, camera.height).value();
    target.bind();
    auto frame = mScene->renderFrame(makeView(camera).value(), selection, style);
    EXPECT_TRUE(frame.ok()) << (frame ? "" : frame.error().message);
    if (stats && frame) *stats = *frame;
    return target.readPixels();
  }

  static size_t countColor(const Image& image, std::array<uint8_t, 3> c) {
    size_t n = 0;
    for (size_t i = 0; i < image.rgba.size(); i += 4)
      n += image.rgba[i] == c[0] && image.rgba[i + 1] == c[1] && image.rgba[i + 2] == c[2];
    return n;
  }

  // Crater Lake is 513 x 513 samples of 20.1 x 27.3 m: about 10.3 x 14.0 km.
  static Camera oblique() {
    Camera c;
    c.eye = {5500, 2500, 3000};  // over the south-west rim, towards the lake
    c.target = {8800, 7500, 1900};
    c.width = 480;
    c.height = 360;
    return c;
  }

  static inline TempDir* sDir = nullptr;
  std::unique_ptr<GlContext> mContext;
  std::unique_ptr<TerrainScene> mScene;
};

TEST_F(TerrainRender, ObliqueViewMatchesGoldenImage) {
  SelectionOptions selection;
  selection.tau = 2.0;
  FrameStats stats;
  const Image image = render(oblique(), selection, TerrainStyle{}, &stats);
  EXPECT_GE(stats.selection.selected, 2u);
  EXPECT_EQ(stats.draw.missing, 0u);
  EXPECT_EQ(stats.draw.drawCalls, 2u) << "sky plus one multi-draw for every chunk";
  const auto result = test::compareWithGolden(image, "crater_lake_oblique");
  EXPECT_TRUE(result.matches) << result.message;
}

TEST_F(TerrainRender, LevelColoursShowSeveralLevels) {
  SelectionOptions selection;
  selection.tau = 0.5;
  TerrainStyle style;
  style.colorBy = ColorBy::kLevel;
  FrameStats stats;
  const Image image = render(oblique(), selection, style, &stats);
  EXPECT_GE(stats.selection.deepestLevel, 2);
  const auto result = test::compareWithGolden(image, "crater_lake_levels");
  EXPECT_TRUE(result.matches) << result.message;
}

TEST_F(TerrainRender, SkirtsCloseTheCracksBetweenLevels) {
  // Looking down 60 degrees from low over the rim, with a small τ: many levels and morph
  // states meet in view and the terrain fills the whole image. Without skirts the background
  // shows through the cracks; with them, never.
  Camera c;
  c.eye = {3000, 4000, 2600};
  c.target = c.eye + glm::dvec3(0.0, 1.0, -std::sqrt(3.0)) * 500.0;
  c.width = 320;
  c.height = 240;
  SelectionOptions selection;
  selection.tau = 0.7;
  TerrainStyle style;
  style.sky = false;
  style.background = kMagenta;
  size_t cracked = 0, closed = 0;
  for (int step = 0; step < 6; ++step) {
    c.eye.y += 150.0;
    c.target.y += 150.0;
    style.skirts = false;
    cracked += countColor(render(c, selection, style), kMagenta);
    style.skirts = true;
    closed += countColor(render(c, selection, style), kMagenta);
  }
  EXPECT_GT(cracked, 0u) << "the view shows no level transitions: the test proves nothing";
  EXPECT_EQ(closed, 0u);
}

}  // namespace
}  // namespace terralod
