// The error figure counts only frames that show what they want. A late split (children that
// arrive after their parent should already have split) eases in from the parent's surface over
// 16 frames to hide the pop; while it does, the chunk is drawn above its morph schedule and so
// coarser than wanted, over τ. Those frames are counted apart (`easing_frames`, part of
// `coarser_than_wanted_frames`), like frames waiting for chunks.

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "cli_runner.h"

namespace terralod::test {
namespace {

TEST(LateSplits, EasingFramesAreCountedApartAndTheBoundHoldsOnTheRest) {
  // A flat plain at 64.8°N (13.2 x 31.0 m cells, 127-163 m): the climb's first frames draw the
  // root while its children stream in; they arrive late and ease in (2.1 px on frame 3 here).
  TempDir dir;
  const std::string source = testData("n43w123_flat_64n.tif");
  const RunResult built = runTerralod({"build", source, "-o", dir.file("f.tlod")});
  ASSERT_EQ(built.exitCode, 0) << built.err;
  const RunResult r =
      runTerralod({"bench", dir.file("f.tlod"), "--auto-flight", "--climb-only", "--frames", "30",
                   "--size", "640x480", "--source", source, "--json", dir.file("b.json")});
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const auto j = nlohmann::json::parse(readWholeFile(dir.file("b.json")));
  EXPECT_GT(j["easing_frames"].get<int>(), 0);
  EXPECT_GE(j["coarser_than_wanted_frames"].get<int>(), j["easing_frames"].get<int>());
  // The frames counted apart do exceed τ (so counting them would break the bound) ...
  EXPECT_GT(j["max_error_px_all"].get<double>(), 2.0);
  // ... and every other frame holds it.
  EXPECT_LE(j["max_error_px"].get<double>(), 2.0);
  EXPECT_GT(j["max_error_px"].get<double>(), 0.0);
}

}  // namespace
}  // namespace terralod::test
