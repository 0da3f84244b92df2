// The bench's figures on VIPM tilesets, measured on the surface the VIPM kind draws: its error
// stays within τ (the kind draws each chunk within θ = τ·D/K); without geomorphing a collapse
// shows as a pop, which geomorphing takes away (the surface still moves between frames, the
// morph step, but continuously).

#include "terralod/measure/vipm_quality.h"

#include <gtest/gtest.h>

#include "temp_dir.h"
#include "terralod/build/builder.h"
#include "terralod/verify/verifier.h"
#include "terralod/vipm/vipm_blob.h"

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
  // A descent in 12 m steps: chunks' θ shrink, collapses are undone along the way.
  View previous = view(0.3, 0.1, 800.0);
  for (int i = 1; i <= 60; ++i) {
    const View current = view(0.3, 0.1, 800.0 - 12.0 * i);
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
  // Geomorphing is continuous in θ: last frame's collapses carried on to this frame's θ (those
  // entering or leaving the geomorph within the step too) draw what this frame draws.
  EXPECT_LT(worstOn, 1e-3) << worstOn << " vs " << worstOff;
  // The surface does move between the frames while it geomorphs.
  EXPECT_GT(worstStep, 10 * worstOn) << worstStep << " vs " << worstOn;
}

TEST_F(VipmQualityTest, AMergeIsComparedWithWhatItReplacedNotWithItsNeighbours) {
  // A root takes over from its children at the roots' level error: its finest level is its
  // children's coarsest, so nothing moves. Its neighbour, a root drawn near its coarsest level
  // and geomorphing, drew their shared border differently (flanges hide that); it is not what
  // the root replaced.
  const auto& nodes = mTileset->nodes();
  uint32_t west = kNoNode, east = kNoNode;
  for (uint32_t a = 0; a < mTree->rootCount() && east == kNoNode; ++a)
    for (uint32_t b = 0; b < mTree->rootCount(); ++b)
      if (nodes[b].y == nodes[a].y && nodes[b].x == nodes[a].x + 1 &&
          mTree->node(a).childCount == 4) {
        west = a;
        east = b;
        break;
      }
  ASSERT_NE(east, kNoNode);
  auto eastBlob = mTileset->readNode(east);
  ASSERT_TRUE(eastBlob.ok());
  auto eastChunk = loadVipmChunk(eastBlob->mesh(), "east");
  ASSERT_TRUE(eastChunk.ok()) << eastChunk.error().message;
  ASSERT_FALSE(eastChunk->unpacked.mesh.errors.empty());
  // Its last collapse geomorphs at θ = 1.5 × its error, and moves on a very little this frame.
  const double coarse = 1.5 * eastChunk->unpacked.mesh.errors.back();
  const double merge = mTree->levelError(0);
  std::vector<VipmQuality::Drawn> before{{east, coarse, coarse}}, after{{east, coarse, coarse}};
  after[0].morphTheta *= 1.0 + 1e-9;
  after.push_back({west, merge, merge});
  const ChunkNode& n = mTree->node(west);
  for (uint32_t c = n.firstChild; c < n.firstChild + n.childCount; ++c)
    before.push_back({c, merge, merge});

  const Box& box = mTree->node(west).box;
  Camera camera;
  camera.width = 320;
  camera.height = 240;
  camera.eye = {box.max[0], box.min[1] - 500.0, box.max[2] + 1500.0};
  camera.target = {box.max[0], 0.5 * (box.min[1] + box.max[1]), box.min[2]};
  const View v = makeView(camera).value();
  VipmQuality quality(*mTileset, *mTree, *mSource, 1, 2, Geomorph::kOn);
  EXPECT_LT(quality.maxPopPixels(v, before, after).value(), 0.01);
  // The root at its coarsest level instead: the merge does show.
  after[1].theta = after[1].morphTheta = 1e9;
  EXPECT_GT(quality.maxPopPixels(v, before, after).value(), 0.5);
}

}  // namespace
}  // namespace terralod
