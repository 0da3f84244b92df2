// Textured tilesets through EGL: the Landsat image draped over the Zion DEM (golden image), and
// chunk borders that show no seam: four children drawn fully morphed (the parent's geometry)
// must look like their parent drawn alone, along their shared borders as much as anywhere.

#include <gtest/gtest.h>

#include <cmath>

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

class TexturedRender : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    // Built once for every test process of this build of the tests.
    sDir = new SharedDirectory(
        test::sharedDirectory("zion-landsat", test::selfStamp(), [](const std::string& dir) {
          BuildOptions options;
          options.input = test::testData("zion_srtm3_utm12_30m.tif");
          options.textureImage = test::testData("zion_landsat8_rgb_utm12_30m.tif");
          options.output = dir + "/zion.tlod";
          NullProgress progress;
          auto built = buildTileset(options, progress, [](const std::string&) {});
          return built.ok() ? std::string() : built.error().message;
        }));
    ASSERT_EQ(sDir->error, "");
  }
  static void TearDownTestSuite() { delete sDir; }

  void SetUp() override {
    test::HeadlessScene opened;
    ASSERT_EQ(test::openHeadlessScene(sDir->file("zion.tlod"), test::Frames::kComplete, opened),
              "");
    mContext = std::move(opened.context);
    mScene = std::move(opened.scene);
    ASSERT_TRUE(mScene->tileset().header().textured());
  }
  void TearDown() override {
    mScene.reset();
    mContext.reset();
  }

  Image draw(const Camera& camera, std::span<const SelectedChunk> chunks) {
    auto target = Framebuffer::create(camera.width, camera.height).value();
    target.bind();
    const DrawStats drawn = mScene->drawChunks(makeView(camera).value(), chunks, TerrainStyle{});
    EXPECT_EQ(drawn.missing, 0u);
    return target.readPixels();
  }

  static inline SharedDirectory* sDir = nullptr;
  std::unique_ptr<GlContext> mContext;
  std::unique_ptr<TerrainScene> mScene;
};

TEST_F(TexturedRender, LandsatDrapedOverZionMatchesGoldenImage) {
  // From the south over the Virgin River's canyon towards the Kolob plateau.
  Camera c;
  c.eye = {14000, 3000, 5200};
  c.target = {17500, 19000, 1600};
  c.width = 480;
  c.height = 360;
  auto target = Framebuffer::create(c.width, c.height).value();
  target.bind();
  SelectionOptions selection;
  selection.tau = 2.0;
  auto frame = mScene->renderFrame(makeView(c).value(), selection, TerrainStyle{});
  ASSERT_TRUE(frame.ok()) << frame.error().message;
  EXPECT_GE(frame->selection.selected, 4u);
  EXPECT_EQ(frame->draw.missing, 0u);
  const auto result = test::compareWithGolden(target.readPixels(), "zion_landsat_oblique");
  EXPECT_TRUE(result.matches) << result.message;
}

TEST_F(TexturedRender, ChildrenShowNoSeamAgainstTheirParent) {
  const ChunkTree& tree = mScene->tree();
  // A level-3 chunk with four children, well inside the data.
  uint32_t parent = kNoNode;
  for (uint32_t i = 0; i < tree.nodes().size(); ++i) {
    const ChunkNode& n = tree.node(i);
    if (n.level == 3 && n.childCount == 4 && n.box.min[0] > 5000 && n.box.min[1] > 5000) {
      parent = i;
      break;
    }
  }
  ASSERT_NE(parent, kNoNode);
  const ChunkNode& p = tree.node(parent);
  const ChunkNode& sw = tree.node(p.firstChild);
  // Straight down (almost) over the border between the SW and SE children: the border line
  // x = borderX is the image's centre column.
  const double borderX = sw.box.max[0];
  const double y = 0.5 * (sw.box.min[1] + sw.box.max[1]);
  Camera c;
  c.eye = {borderX, y, p.box.max[2] + 1200.0};
  c.target = {borderX, y + 1.0, p.box.max[2] - 1000.0};
  c.width = 320;
  c.height = 240;
  {
    // A frame that wants the children makes them (and so the parent) resident.
    auto target = Framebuffer::create(c.width, c.height).value();
    target.bind();
    SelectionOptions fine;
    fine.tau = 0.25;
    ASSERT_TRUE(mScene->renderFrame(makeView(c).value(), fine, TerrainStyle{}).ok());
  }
  const SelectedChunk whole[] = {{parent, 0.0f}};
  std::vector<SelectedChunk> children;
  for (uint32_t k = 0; k < 4; ++k) children.push_back({p.firstChild + k, 1.0f});
  const Image reference = draw(c, whole);
  const Image split = draw(c, children);

  // Mean |difference| per image column, 8-bit units.
  std::vector<double> column(size_t(c.width), 0.0);
  for (int yy = 0; yy < c.height; ++yy)
    for (int x = 0; x < c.width; ++x) {
      const auto a = reference.pixel(x, yy), b = split.pixel(x, yy);
      for (int ch = 0; ch < 3; ++ch) column[size_t(x)] += std::abs(int(a[ch]) - int(b[ch]));
    }
  for (double& v : column) v /= 3.0 * c.height;
  double seam = 0, elsewhere = 0;
  int elsewhereCount = 0;
  for (int x = 0; x < c.width; ++x) {
    if (std::abs(x - c.width / 2) <= 2) {
      seam = std::max(seam, column[size_t(x)]);
    } else {
      elsewhere += column[size_t(x)];
      ++elsewhereCount;
    }
  }
  elsewhere /= elsewhereCount;
  // Border texels agree exactly before compression; BC1's per-block fit leaves up to its own
  // error between the two encodings of a border (measured: 1.98/255 on the border columns at
  // this 10x magnification, 0.006/255 elsewhere), under the 1-2 % of a just-visible line.
  EXPECT_LT(seam, 3.0) << "a line along the chunk border (mean difference " << seam
                       << "/255 on the border columns, " << elsewhere << "/255 elsewhere)";
}

TEST_F(TexturedRender, ParentShowsItsChildrensTexelsAtEveryMip) {
  // Zion's levels are all source-limited: each holds its children's texels unresampled, and
  // its mips are theirs side by side. Seen from far away (mips 1 and up), the root must look
  // like its children fully morphed: the merge the automatic flight's climb makes.
  const ChunkTree& tree = mScene->tree();
  const ChunkNode& root = tree.node(0);
  ASSERT_GT(root.childCount, 1u);
  Camera c;
  c.eye = {27468, 34780, 7340};
  c.target = {17000, 21000, 1500};
  c.width = 320;
  c.height = 240;
  {
    auto target = Framebuffer::create(c.width, c.height).value();
    target.bind();
    SelectionOptions fine;
    fine.tau = 0.5;  // wants the root's children: both levels become resident
    ASSERT_TRUE(mScene->renderFrame(makeView(c).value(), fine, TerrainStyle{}).ok());
  }
  const SelectedChunk whole[] = {{0, 0.0f}};
  std::vector<SelectedChunk> children;
  for (uint32_t k = 0; k < root.childCount; ++k) children.push_back({root.firstChild + k, 1.0f});
  const Image parent = draw(c, whole);
  const Image split = draw(c, children);
  double sum = 0;
  size_t terrain = 0;
  for (int y = 0; y < c.height; ++y)
    for (int x = 0; x < c.width; ++x) {
      const auto a = parent.pixel(x, y), b = split.pixel(x, y);
      for (int ch = 0; ch < 3; ++ch) sum += std::abs(int(a[ch]) - int(b[ch]));
      terrain += a != split.pixel(0, 0) ? 1 : 0;
    }
  ASSERT_GT(terrain, size_t(c.width * c.height / 2)) << "the view must show the terrain";
  // Sampled where the builder put the texels, the two agree; GL's own sampling of the mosaic
  // mips shifts them by up to half a texel: 0.76/255 here.
  const double mean = sum / (3.0 * c.width * c.height);
  EXPECT_LT(mean, 0.1) << "mean difference " << mean << "/255 between the root and its children";
}

}  // namespace
}  // namespace terralod
