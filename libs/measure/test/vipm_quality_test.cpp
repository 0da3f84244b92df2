// The bench's figures on VIPM tilesets, measured on the surface the VIPM kind draws: its error
// stays within τ (the kind draws each chunk within θ = τ·D/K); without geomorphing a collapse
// shows as a pop, which geomorphing takes away (the surface still moves between frames, the
// morph step, but continuously).

#include "terralod/measure/vipm_quality.h"

#include <gtest/gtest.h>

#include "temp_dir.h"
#include "terralod/build/builder.h"
#include "terralod/verify/verifier.h"

namespace terralod {
namespace {

class VipmQualityTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    sDir = new test::TempDir;
    BuildOptions options;
    options.input = test::testData("crater_lake_0513.bt");
    options.output = sDir->file("crater.tlod");
    options.kind = TilesetKind::kVipm;
    NullProgress progress;
    auto built = buildTileset(options, progress, [](const std::string&) {});
    ASSERT_TRUE(built.ok()) << built.error().message;
  }
  static void TearDownTestSuite() { delete sDir; }

  void SetUp() override {
    auto tileset = TilesetReader::openFile(sDir->file("crater.tlod"));
    ASSERT_TRUE(tileset.ok()) << tileset.error().message;
    mTileset = std::move(tileset).value();
    ASSERT_EQ(mTileset->header().meshKind, MeshKind::kVipm);
    auto source = loadTilesetSource(*mTileset, test::testData("crater_lake_0513.bt"));
    ASSERT_TRUE(source.ok()) << source.error().message;
    mSource.emplace(std::move(source).value());
    mTree.emplace(mTileset->header(), mTileset->nodes());
  }

  // A camera `height` metres over the data's top, at fraction (fx, fy) of its extent, looking
  // at its centre.
  View view(double fx, double fy, double height) const {
    const Box& e = mTree->extent();
    Camera camera;
    camera.width = 320;
    camera.height = 240;
    camera.eye = {e.min[0] + fx * (e.max[0] - e.min[0]), e.min[1] + fy * (e.max[1] - e.min[1]),
                  e.max[2] + height};
    camera.target = {0.5 * (e.min[0] + e.max[0]), 0.5 * (e.min[1] + e.max[1]), e.min[2]};
    return makeView(camera).value();
  }

  std::vector<VipmQuality::Drawn> drawn(const View& v, double tau) const {
    SelectionOptions options;
    options.tau = tau;
    std::vector<SelectedChunk> selection;
    selectChunks(*mTree, v, options, selection);
    return VipmQuality::drawn(*mTree, v, tau, selection);
  }

  static inline test::TempDir* sDir = nullptr;
  std::unique_ptr<TilesetReader> mTileset;
  std::optional<Heightfield> mSource;
  std::optional<ChunkTree> mTree;
};

TEST_F(VipmQualityTest, DrawnErrorStaysWithinTauAndGrowsWithIt) {
  VipmQuality quality(*mTileset, *mTree, *mSource, 1, 2, Geomorph::kOn);
  int measured = 0;
  for (double tau : {1.0, 4.0})
    for (double fx : {0.1, 0.7})
      for (double height : {50.0, 600.0}) {
        const View v = view(fx, 0.2, height);
        const double error = quality.maxErrorPixels(v, drawn(v, tau)).value();
        EXPECT_LE(error, tau) << "tau " << tau << " fx " << fx << " height " << height;
        measured += error > 0.25 * tau;
      }
  // The drawn surface is not the source: the figures measure something.
  EXPECT_GE(measured, 4);
}

TEST_F(VipmQualityTest, CollapsesPopWithoutGeomorphingAndNotWithIt) {
  VipmQuality morphed(*mTileset, *mTree, *mSource, 1, 2, Geomorph::kOn);
  VipmQuality unmorphed(*mTileset, *mTree, *mSource, 1, 2, Geomorph::kOff);
  double worstOn = 0.0, worstOff = 0.0, worstStep = 0.0;
  SelectionOptions options;
  options.tau = 2.0;
  // A descent in 3 m steps: chunks' θ shrink, collapses are undone along the way.
  View previous = view(0.3, 0.1, 800.0);
  for (int i = 1; i <= 60; ++i) {
    const View current = view(0.3, 0.1, 800.0 - 3.0 * i);
    std::vector<SelectedChunk> selection;
    selectChunks(*mTree, previous, options, selection);
    const auto before = VipmQuality::drawn(*mTree, previous, options.tau, selection);
    const auto beforeNow = VipmQuality::geomorphedFor(*mTree, current, options, selection, before);
    const auto after = drawn(current, options.tau);
    worstOn = std::max(worstOn, morphed.maxPopPixels(current, beforeNow, after).value());
    worstStep = std::max(worstStep, morphed.maxPopPixels(current, before, after).value());
    worstOff = std::max(worstOff, unmorphed.maxPopPixels(current, beforeNow, after).value());
    // The same drawn state twice: nothing moves.
    if (i % 20 == 0) {
      EXPECT_EQ(unmorphed.maxPopPixels(current, after, after).value(), 0.0);
    }
    previous = current;
  }
  EXPECT_GT(worstOff, 0.5);
  // Geomorphing is continuous in θ: only a collapse entering the geomorph within the step is
  // left, a fraction of the step.
  EXPECT_LT(worstOn, 0.1) << worstOn << " vs " << worstOff;
  // The surface does move between the frames while it geomorphs.
  EXPECT_GT(worstStep, 10 * worstOn) << worstStep << " vs " << worstOn;
}

}  // namespace
}  // namespace terralod
