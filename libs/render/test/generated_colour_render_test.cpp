// The generated colour made by the shader (format version 6) through EGL: Mount Rainier (SRTM
// 3", 46.9°N: snow above the latitude's snow line, rock, forest-green lowland) from the south-
// west, against a golden image and against the same build with the colour baked into the
// texture (--bake-colour, version 5), which the shader's colour must reproduce.

#include <gtest/gtest.h>

#include <cstdio>

#include "headless_scene.h"
#include "image_compare.h"
#include "shared_directory.h"
#include "terralod/build/builder.h"
#include "terralod/render/framebuffer.h"
#include "terralod/render/gl_context.h"
#include "terralod/render/terrain_scene.h"

namespace terralod {
namespace {

using test::SharedDirectory;

class GeneratedColourRender : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    sDir = new SharedDirectory(
        test::sharedDirectory("rainier-colour", test::selfStamp(), [](const std::string& dir) {
          for (GeneratedColour colour : {GeneratedColour::kShader, GeneratedColour::kBaked}) {
            BuildOptions options;
            options.input = test::testData("osgearth_mt_rainier_90m.tif");
            options.output =
                dir + (colour == GeneratedColour::kShader ? "/shade.tlod" : "/baked.tlod");
            options.generatedColour = colour;
            NullProgress progress;
            auto built = buildTileset(options, progress, [](const std::string&) {});
            if (!built.ok()) return built.error().message;
          }
          return std::string();
        }));
    ASSERT_EQ(sDir->error, "");
  }
  static void TearDownTestSuite() { delete sDir; }

  // The summit from the south-west at τ = 2.
  static Image render(const std::string& name) {
    test::HeadlessScene opened;
    EXPECT_EQ(test::openHeadlessScene(sDir->file(name), test::Frames::kComplete, opened), "");
    if (!opened.scene) return {};
    Camera c;
    c.eye = {12000, 78000, 6000};
    c.target = {18400, 94800, 3000};
    c.width = 480;
    c.height = 360;
    auto target = Framebuffer::create(c.width, c.height).value();
    target.bind();
    SelectionOptions selection;
    selection.tau = 2.0;
    auto frame = opened.scene->renderFrame(makeView(c).value(), selection, TerrainStyle{});
    EXPECT_TRUE(frame.ok()) << frame.error().message;
    if (!frame.ok()) return {};
    EXPECT_EQ(frame->draw.missing, 0u);
    Image image = target.readPixels();
    opened.scene.reset();
    return image;
  }

  static inline SharedDirectory* sDir = nullptr;
};

TEST_F(GeneratedColourRender, ShadeLayerMatchesGoldenImage) {
  const auto result = test::compareWithGolden(render("shade.tlod"), "rainier_generated_colour");
  EXPECT_TRUE(result.matches) << result.message;
}

TEST_F(GeneratedColourRender, ShadeLayerLooksLikeTheBakedColour) {
  const Image shade = render("shade.tlod");
  const Image baked = render("baked.tlod");
  // The snow, rock and palette come from the drawn height and the normal map instead of
  // the source's heights, the shade at half the texels: a few pixels by the snow's edge
  // differ by more than 8 grey levels (written: 29 of 172,800, mean 0.51/255).
  const auto result = test::compareImages(shade, baked, {8, 0.001});
  std::printf("shade against baked: %s\n", result.message.c_str());
  EXPECT_TRUE(result.matches) << result.message;
  EXPECT_LT(result.meanAbsoluteError, 1.0);
}

}  // namespace
}  // namespace terralod
