// VIPM tilesets as `terralod build --kind vipm` writes them (a 257² synthetic DEM, materials
// from its classification), drawn through EGL: an automatic flight streams them without a hole,
// and flanges, materials and geomorphing show as they should.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <set>

#include "headless_scene.h"
#include "shared_directory.h"
#include "terralod/build/builder.h"
#include "terralod/raster/synthetic_dem_writer.h"
#include "terralod/render/framebuffer.h"
#include "terralod/render/gl_context.h"
#include "terralod/render/terrain_scene.h"
#include "terralod/runtime/flight.h"

namespace terralod {
namespace {

using test::SharedDirectory;

// Background pixels below terrain in their column (see vipm_render_test.cpp).
uint64_t holes(const Image& image, const TerrainStyle& style = {}) {
  uint64_t n = 0;
  for (int x = 0; x < image.width; ++x) {
    bool terrain = false;
    for (int y = 0; y < image.height; ++y) {
      const auto p = image.pixel(x, y);
      const bool background =
          p[0] == style.background[0] && p[1] == style.background[1] && p[2] == style.background[2];
      terrain = terrain || !background;
      n += terrain && background;
    }
  }
  return n;
}

class VipmTilesetRender : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    sDir = new SharedDirectory(
        test::sharedDirectory("vipm-synth-257", test::selfStamp(), [](const std::string& dir) {
          SyntheticDemOptions synth;
          synth.output = dir + "/synth.tif";
          synth.columns = synth.rows = 257;
          synth.spacing = 30.0;
          NullProgress progress;
          if (auto s = writeSyntheticDem(synth, progress); !s) return s.error().message;
          BuildOptions options;
          options.input = synth.output;
          options.output = dir + "/synth.tlod";
          options.kind = decltype(options.kind)::kVipm;
          auto built = buildTileset(options, progress, [](const std::string&) {});
          return built.ok() ? std::string() : built.error().message;
        }));
    ASSERT_EQ(sDir->error, "");
  }
  static void TearDownTestSuite() { delete sDir; }

  void TearDown() override {
    mScene.reset();
    mContext.reset();
  }
  void open(test::Frames frames) {
    test::HeadlessScene opened;
    ASSERT_EQ(test::openHeadlessScene(sDir->file("synth.tlod"), frames, opened), "");
    mContext = std::move(opened.context);
    mScene = std::move(opened.scene);
    ASSERT_EQ(mScene->tileset().header().meshKind, MeshKind::kVipm);
  }
  Image draw(const Camera& camera, const SelectionOptions& selection, TerrainStyle style,
             FrameStats* stats = nullptr) {
    auto target = Framebuffer::create(camera.width, camera.height).value();
    target.bind();
    style.sky = false;
    style.haze = 0.0;
    auto drawn = mScene->renderFrame(makeView(camera).value(), selection, style);
    EXPECT_TRUE(drawn.ok()) << drawn.error().message;
    if (stats && drawn.ok()) *stats = *drawn;
    return target.readPixels();
  }

  static inline SharedDirectory* sDir = nullptr;
  std::unique_ptr<GlContext> mContext;
  std::unique_ptr<TerrainScene> mScene;
};

TEST_F(VipmTilesetRender, TheLowPassStreamsWithoutAHole) {
  // Streaming (no waiting for loads): roots first, leaves as they arrive, late splits easing.
  open(test::Frames::kStreamed);
  const Flight flight = autoFlight(mScene->tree(), 240, 180, 60.0, 0);
  const std::vector<Camera> cameras = flightCameras(flight);
  ASSERT_GT(flight.climbStart, 40);
  uint64_t worst = 0;
  uint32_t leavesDrawn = 0;
  // The first frames: the roots, then leaves arriving (the ones that found a root's
  // T-junctions before roots had interior flanges).
  for (int i = 0; i < 40; ++i) {
    FrameStats stats;
    const uint64_t h = holes(draw(cameras[size_t(i)], {}, {}, &stats));
    EXPECT_EQ(h, 0u) << "frame " << i;
    worst = std::max(worst, h);
    leavesDrawn = std::max(leavesDrawn, stats.draw.chunks);
    EXPECT_EQ(stats.draw.missing, 0u);
  }
  EXPECT_EQ(worst, 0u);
  EXPECT_GT(leavesDrawn, 4u);
}

TEST_F(VipmTilesetRender, RootsCloseTheirChildrensSharedSides) {
  // The roots alone (what streaming draws first) from the low pass's first cameras: a root
  // joins its children's coarsest levels, whose shared sides need not match.
  open(test::Frames::kComplete);
  std::vector<SelectedChunk> roots;
  for (uint32_t r = 0; r < mScene->tree().rootCount(); ++r) roots.push_back({r, 0.0f});
  const Flight flight = autoFlight(mScene->tree(), 240, 180, 60.0, 0);
  const std::vector<Camera> cameras = flightCameras(flight);
  TerrainStyle style;
  style.sky = false;
  for (int i = 0; i < 40; i += 2) {
    auto target = Framebuffer::create(cameras[size_t(i)].width, cameras[size_t(i)].height).value();
    target.bind();
    const DrawStats drawn = mScene->drawChunks(makeView(cameras[size_t(i)]).value(), roots, style);
    EXPECT_EQ(drawn.missing, 0u);
    EXPECT_EQ(holes(target.readPixels()), 0u) << "camera " << i;
  }
}

TEST_F(VipmTilesetRender, FlangesMaterialsAndGeomorphsShow) {
  open(test::Frames::kComplete);
  const Flight flight = autoFlight(mScene->tree(), 320, 240, 60.0, 0);
  const Camera c = flightCameras(flight)[size_t(flight.climbStart / 2)];
  TerrainStyle noSkirts;
  noSkirts.skirts = false;
  SelectionOptions noMorph;
  noMorph.morph = false;
  const Image with = draw(c, {}, {});
  const Image without = draw(c, {}, noSkirts);
  const Image popped = draw(c, noMorph, {});
  EXPECT_EQ(holes(with), 0u);
  EXPECT_GT(holes(without), 0u);
  uint64_t differ = 0;
  for (size_t i = 0; i < with.rgba.size(); ++i) differ += with.rgba[i] != popped.rgba[i];
  EXPECT_GT(differ, 100u);
  // Several materials in view: the pixels' colours, coarsely binned, fall into many bins.
  std::set<int> bins;
  for (size_t i = 0; i < with.rgba.size(); i += 4)
    bins.insert((with.rgba[i] / 32) * 64 + (with.rgba[i + 1] / 32) * 8 + with.rgba[i + 2] / 32);
  EXPECT_GT(bins.size(), 12u);
}

TEST_F(VipmTilesetRender, FansCloseEveryBorderWithoutFlanges) {
  // The low pass (ground below the horizon in every column, as holes() needs), every chunk
  // stitched by fans and nothing below the surface: no hole in any frame, and the picture is
  // the flanges' one but along the borders.
  open(test::Frames::kComplete);
  const Flight flight = autoFlight(mScene->tree(), 240, 180, 60.0, 0);
  const std::vector<Camera> cameras = flightCameras(flight);
  TerrainStyle fans, none;
  fans.stitch = none.stitch = VipmStitch::kFans;
  none.skirts = false;
  uint64_t holesWithout = 0, fanChanges = 0;
  double differ = 0.0;
  int frames = 0;
  for (size_t i = 0; i < size_t(flight.climbStart); i += 20) {
    FrameStats stats;
    const Image stitched = draw(cameras[i], {}, fans, &stats);
    EXPECT_EQ(holes(stitched), 0u) << "frame " << i;
    EXPECT_EQ(stats.draw.missing, 0u);
    fanChanges += stats.fanChangeMs.size();
    EXPECT_FALSE(std::isnan(stats.fanFrameMs));
    holesWithout += holes(draw(cameras[i], {}, none));
    const Image flanged = draw(cameras[i], {}, {});
    uint64_t d = 0;
    for (size_t k = 0; k < stitched.rgba.size(); ++k) d += stitched.rgba[k] != flanged.rgba[k];
    differ += double(d) / double(stitched.rgba.size());
    ++frames;
  }
  EXPECT_GT(fanChanges, 0u);
  EXPECT_GT(holesWithout, 0u);
  EXPECT_LT(differ / frames, 0.05);  // borders only
}

// Mean absolute difference of two images' colour channels, in 8-bit units.
double meanDifference(const Image& a, const Image& b) {
  double sum = 0.0;
  for (size_t i = 0; i < a.rgba.size(); ++i)
    if (i % 4 != 3) sum += std::abs(int(a.rgba[i]) - int(b.rgba[i]));
  return sum / double(a.rgba.size() / 4 * 3);
}

TEST_F(VipmTilesetRender, BlotsDrawFarChunksInOnePassAndTheSwitchDoesNotShow) {
  // Low views over the synth with blots from 4 px a cell (the tileset is small): far chunks
  // are blots, fewer draw calls; the picture is the one with those chunks drawn per material,
  // faded as they are toward the blots (what a blot replaces), within half a level of 8 bits;
  // without the fade it is not.
  open(test::Frames::kComplete);
  const Flight flight = autoFlight(mScene->tree(), 320, 240, 60.0, 0);
  const std::vector<Camera> cameras = flightCameras(flight);
  TerrainStyle blots, faded, off;
  blots.blotCellPixels = faded.blotCellPixels = off.blotCellPixels = 4.0;
  faded.blots = VipmBlots::kFadeOnly;
  off.blots = VipmBlots::kOff;
  uint32_t blotted = 0;
  double worstSwitch = 0.0, unfaded = 0.0;
  for (size_t i = 0; i < size_t(flight.climbStart); i += 300) {
    FrameStats withBlots, without;
    const Image a = draw(cameras[i], {}, blots, &withBlots);
    const Image b = draw(cameras[i], {}, faded, &without);
    const Image c = draw(cameras[i], {}, off);
    blotted += withBlots.draw.blots;
    EXPECT_EQ(without.draw.blots, 0u);
    if (withBlots.draw.blots > 0) {
      EXPECT_LT(withBlots.draw.drawCalls, without.draw.drawCalls);
    }
    worstSwitch = std::max(worstSwitch, meanDifference(a, b));
    unfaded = std::max(unfaded, meanDifference(a, c));
  }
  EXPECT_GT(blotted, 0u);
  EXPECT_LT(worstSwitch, 0.5);
  EXPECT_GT(unfaded, 0.5);
  EXPECT_GT(unfaded, 10.0 * worstSwitch);
  std::printf("blots %u, switch %.3f/255, without the fade %.3f/255\n", blotted, worstSwitch,
              unfaded);
}

TEST_F(VipmTilesetRender, SuperChunksDrawABlocksBlotsInOneCallAndChangeNoPixel) {
  // The same low views with a super-chunk's blots in one call and each in its own, with
  // flanges and with fans: fewer calls, the same picture (the same floats summed per vertex;
  // only where a flange and a surface meet at equal depth may the order of the calls show),
  // and no hole with fans.
  open(test::Frames::kComplete);
  const Flight flight = autoFlight(mScene->tree(), 320, 240, 60.0, 0);
  const std::vector<Camera> cameras = flightCameras(flight);
  uint32_t calls = 0, blotsInCalls = 0;
  double worst = 0.0;  // of the channel values that differ
  for (VipmStitch stitch : {VipmStitch::kFlanges, VipmStitch::kFans}) {
    TerrainStyle on, off;
    on.blotCellPixels = off.blotCellPixels = 4.0;
    on.stitch = off.stitch = stitch;
    off.superChunks = VipmSuperChunks::kOff;
    for (size_t i = 0; i < size_t(flight.climbStart); i += 300) {
      FrameStats with, without;
      const Image a = draw(cameras[i], {}, on, &with);
      const Image b = draw(cameras[i], {}, off, &without);
      EXPECT_EQ(without.draw.superChunks, 0u);
      EXPECT_EQ(with.draw.blots, without.draw.blots);
      EXPECT_EQ(with.draw.triangles, without.draw.triangles);
      // Each blot alone: its surface, and its flanges.
      const uint32_t perBlot = stitch == VipmStitch::kFlanges ? 2 : 1;
      EXPECT_EQ(with.draw.drawCalls - with.draw.superChunks + with.draw.superChunkBlots * perBlot,
                without.draw.drawCalls);
      calls += with.draw.superChunks;
      blotsInCalls += with.draw.superChunkBlots;
      uint64_t differ = 0;
      for (size_t k = 0; k < a.rgba.size(); ++k) differ += a.rgba[k] != b.rgba[k];
      worst = std::max(worst, double(differ) / double(a.rgba.size()));
      EXPECT_LT(double(differ) / double(a.rgba.size()), 1e-3) << "frame " << i;
      if (stitch == VipmStitch::kFans) {
        EXPECT_EQ(holes(a), 0u) << "frame " << i;
      }
    }
  }
  EXPECT_GT(calls, 0u);
  EXPECT_GT(blotsInCalls, 2 * calls - 1);
  std::printf("%u super-chunk calls drew %u blots; at most %.2g of the values differ\n", calls,
              blotsInCalls, worst);
}

TEST_F(VipmTilesetRender, MaterialIdImagesCoverTheTerrainWithItsMaterials) {
  open(test::Frames::kComplete);
  const Flight flight = autoFlight(mScene->tree(), 320, 240, 60.0, 0);
  const Camera c = flightCameras(flight)[size_t(flight.climbStart / 2)];
  const View view = makeView(c).value();
  SelectionOptions noMorph;
  noMorph.morph = false;
  TerrainStyle style;
  const Image colour = draw(c, noMorph, style);
  std::vector<VipmChunkAt> chunks, coarser;
  for (const SelectedChunk& s : mScene->selected()) {
    const double theta = vipmDrawnTheta(mScene->tree(), view, noMorph.tau, s);
    chunks.push_back({s.node, theta});
    coarser.push_back({s.node, theta * 8.0});
  }
  auto target = Framebuffer::create(c.width, c.height).value();
  target.bind();
  EXPECT_EQ(mScene->drawVipmMaterials(view, chunks, style, noMorph).missing, 0u);
  const Image ids = target.readPixels();
  mScene->drawVipmMaterials(view, coarser, style, noMorph);
  const Image coarse = target.readPixels();
  mScene->drawVipmMaterials(view, chunks, style, noMorph);
  const Image again = target.readPixels();
  EXPECT_EQ(ids.rgba, again.rgba);  // the state drawn, not the history

  // Terrain where the colour image has terrain, several materials, and a coarser level
  // moves some boundaries.
  uint64_t coverageDiffers = 0, materialDiffers = 0;
  std::set<int> materials;
  for (size_t i = 0; i < ids.rgba.size(); i += 4) {
    const int m = vipmMaterialOfPixel(ids.rgba[i]);
    const bool background = colour.rgba[i] == style.background[0] &&
                            colour.rgba[i + 1] == style.background[1] &&
                            colour.rgba[i + 2] == style.background[2];
    coverageDiffers += (m < 0) != background;
    materialDiffers += m != vipmMaterialOfPixel(coarse.rgba[i]);
    if (m >= 0) materials.insert(m);
  }
  EXPECT_EQ(coverageDiffers, 0u);
  EXPECT_GE(materials.size(), 2u);
  EXPECT_GT(materialDiffers, 0u);
}

}  // namespace
}  // namespace terralod
