#include "terralod/runtime/flight.h"

#include <gtest/gtest.h>

#include <cmath>

#include "test_tree.h"

namespace terralod {
namespace {

const char* kFlight = R"({"fov_deg": 45, "size": [640, 480], "frames": 50,
  "keyframes": [{"eye": [0, 0, 100], "target": [0, 100, 0]},
                {"eye": [100, 0, 100], "target": [100, 100, 0]},
                {"eye": [100, 300, 150], "target": [100, 400, 0]}]})";

TEST(Flight, ParsesAndRoundTrips) {
  auto f = parseFlight(kFlight, "f.json");
  ASSERT_TRUE(f.ok()) << f.error().message;
  EXPECT_EQ(f->frames, 50);
  EXPECT_EQ(f->width, 640);
  EXPECT_DOUBLE_EQ(f->fovDegrees, 45.0);
  ASSERT_EQ(f->keyframes.size(), 3u);
  auto again = parseFlight(flightToJson(*f), "again.json");
  ASSERT_TRUE(again.ok());
  EXPECT_EQ(again->keyframes[2].eye, f->keyframes[2].eye);
  EXPECT_EQ(again->frames, 50);
}

TEST(Flight, RejectsBrokenFlightsNamingTheFile) {
  for (
      const char* bad :
      {"", "[]", R"({"keyframes": []})", R"({"keyframes": [{"eye": [0,0,0], "target": [1,1,1]}]})",
       R"({"keyframes": [{"eye": [0,0], "target": [1,1,1]}, {"eye": [0,0,1], "target": [1,1,1]}]})",
       R"({"fov_deg": 0, "keyframes": [{"eye": [0,0,0], "target": [1,1,1]}, {"eye": [0,0,1], "target": [1,1,1]}]})",
       R"({"frames": 0, "keyframes": [{"eye": [0,0,0], "target": [1,1,1]}, {"eye": [0,0,1], "target": [1,1,1]}]})",
       R"({"keyframes": [{"eye": [1,1,1], "target": [1,1,1]}, {"eye": [0,0,1], "target": [1,1,1]}]})"}) {
    auto f = parseFlight(bad, "bad.json");
    ASSERT_FALSE(f.ok()) << bad;
    EXPECT_EQ(f.error().message.rfind("bad.json: ", 0), 0u) << f.error().message;
  }
}

// Found by the flight fuzzer: an eye at 1.5e61 m (finite, so accepted) made the arc-length
// table NaN and the conversion of a NaN to a segment index undefined behaviour; every camera
// came out NaN. Coordinates are bounded now, and flights at the bound fly finite cameras.
TEST(Flight, CoordinatesAreBoundedSoEveryCameraIsFinite) {
  const auto far = parseFlight(R"({"keyframes": [{"eye": [99, 300, 700], "target": [0, 0, 0]},
      {"eye": [1.5e61, -3200, 900], "target": [500, 912, 300]},
      {"eye": [899, 300, 700], "target": [600, 800, 250]}], "frames": 20})",
                               "far.json");
  ASSERT_FALSE(far.ok());
  EXPECT_EQ(far.error().message, "far.json: keyframe 1 eye must be within 1e12 m of the origin");
  auto edge = parseFlight(R"({"keyframes": [{"eye": [-1e12, -1e12, 1e12], "target": [0, 0, 0]},
      {"eye": [1e12, 1e12, -1e12], "target": [-1e12, 1e12, 0]},
      {"eye": [1, 2, 3], "target": [1e12, 0, 0]}], "frames": 50})",
                          "edge.json");
  ASSERT_TRUE(edge.ok()) << edge.error().message;
  for (const Camera& c : flightCameras(*edge)) {
    ASSERT_TRUE(std::isfinite(c.eye.x) && std::isfinite(c.eye.y) && std::isfinite(c.eye.z));
    ASSERT_TRUE(std::isfinite(c.target.x) && std::isfinite(c.target.y) &&
                std::isfinite(c.target.z));
  }
}

TEST(Flight, PassesThroughItsKeyframesAtAnEvenPace) {
  auto f = parseFlight(kFlight, "f.json").value();
  const auto cameras = flightCameras(f);
  ASSERT_EQ(cameras.size(), 50u);
  EXPECT_NEAR(glm::length(cameras.front().eye - f.keyframes.front().eye), 0.0, 1e-6);
  EXPECT_NEAR(glm::length(cameras.back().eye - f.keyframes.back().eye), 0.0, 1e-6);
  double shortest = 1e9, longest = 0;
  for (size_t i = 1; i < cameras.size(); ++i) {
    const double step = glm::length(cameras[i].eye - cameras[i - 1].eye);
    shortest = std::min(shortest, step);
    longest = std::max(longest, step);
  }
  EXPECT_LT(longest / shortest, 1.1) << "steps should be equal arc lengths";
  EXPECT_EQ(cameras[10].width, 640);
}

TEST(Flight, AutoFlightMovesAtMostHalfAPercentOfItsHeightPerFrame) {
  // A flat 10 km square, heights 0..50 m, one level.
  TilesetHeader h;
  h.levelCount = 1;
  h.rootCells = h.leafCells = 1024;
  h.rootsX = h.rootsY = 1;
  h.sourceColumns = h.sourceRows = 1025;
  h.spacingX = h.spacingY = 10.0;
  h.levelError[0] = 1.0;
  h.extentMax = {10240.0, 10240.0, 50.0};
  std::vector<NodeRecord> nodes(1);
  nodes[0].maxZ = 50.0f;
  const ChunkTree tree(h, nodes);
  const Flight f = autoFlight(tree, 320, 240, 60.0);
  ASSERT_GT(f.frames, 100);
  const auto cameras = flightCameras(f);
  ASSERT_EQ(int(cameras.size()), f.frames);
  for (size_t i = 1; i < cameras.size(); ++i) {
    const double above =
        cameras[i - 1].eye.z - groundHeightBound(tree, cameras[i - 1].eye.x, cameras[i - 1].eye.y);
    ASSERT_LE(glm::length(cameras[i].eye - cameras[i - 1].eye), 0.005 * above * 1.0001) << i;
    ASSERT_GT(above, 0.0);
  }
  // It ends high above the whole extent, looking at its centre.
  EXPECT_GT(cameras.back().eye.z, 10000.0);
  EXPECT_NEAR(cameras.back().target.x, 5120.0, 1.0);
  EXPECT_EQ(autoFlight(tree, 320, 240, 60.0, 25).frames, 25);
  const Flight climb = autoFlightClimb(tree, 320, 240, 60.0);
  EXPECT_EQ(climb.frames, f.frames - f.climbStart);
  EXPECT_EQ(climb.keyframes.front().eye, f.keyframes[size_t(f.climbStart)].eye);
}

// A 64 x 48 grid of 100 m cells, gently rolling (ranges of 1–3 m), with a rugged patch in one
// corner: the flight must head there, not to the centre.
ReliefGrid cornerRelief(bool northEast) {
  ReliefGrid g;
  g.columns = 64;
  g.rows = 48;
  g.cellSize = {100.0, 100.0};
  g.range.resize(size_t(g.columns * g.rows));
  for (int j = 0; j < g.rows; ++j)
    for (int i = 0; i < g.columns; ++i) {
      const bool rugged = northEast ? (i >= 48 && j >= 34) : (i < 16 && j < 14);
      g.range[size_t(j * g.columns + i)] =
          rugged ? 300.0 + 200.0 * ((i * 7 + j * 3) % 5) : 1.0 + double((i + 2 * j) % 3);
    }
  return g;
}

Box extentOf(double w, double h) {
  Box e;
  e.max = {w, h, 3000.0};
  return e;
}

TEST(FlightStart, MostRuggedPointIsInTheRuggedCornerAwayFromTheEdge) {
  const Box e = extentOf(6400.0, 4800.0);
  const glm::dvec2 ne = mostRuggedPoint(cornerRelief(true), e);
  EXPECT_GT(ne.x, 0.7 * 6400.0);
  EXPECT_GT(ne.y, 0.7 * 4800.0);
  EXPECT_LE(ne.x, 0.85 * 6400.0);
  EXPECT_LE(ne.y, 0.85 * 4800.0);
  const glm::dvec2 sw = mostRuggedPoint(cornerRelief(false), e);
  EXPECT_LT(sw.x, 0.3 * 6400.0);
  EXPECT_LT(sw.y, 0.3 * 4800.0);
  EXPECT_GE(sw.x, 0.15 * 6400.0);
  EXPECT_GE(sw.y, 0.15 * 4800.0);
  // The same grid gives the same point (no hidden state).
  EXPECT_EQ(mostRuggedPoint(cornerRelief(true), e), ne);
}

TEST(FlightStart, FlatOrTinyDataGivesTheCentre) {
  ReliefGrid flat = cornerRelief(true);
  std::fill(flat.range.begin(), flat.range.end(), 2.0);
  const glm::dvec2 p = mostRuggedPoint(flat, extentOf(6400.0, 4800.0));
  EXPECT_NEAR(p.x, 3200.0, 100.0);
  EXPECT_NEAR(p.y, 2400.0, 100.0);
  ReliefGrid one;
  one.columns = one.rows = 1;
  one.cellSize = {10.0, 10.0};
  one.range = {5.0};
  EXPECT_EQ(mostRuggedPoint(one, extentOf(10.0, 10.0)), glm::dvec2(5.0, 5.0));
  EXPECT_EQ(mostRuggedPoint(ReliefGrid{}, extentOf(10.0, 20.0)), glm::dvec2(5.0, 10.0));
}

TEST(FlightStart, AutoFlightLowPassAndClimbGoToTheMostRuggedCorner) {
  // 1024 m square, 5 levels (16 x 16 leaves of 64 m): leaves in the south-east corner span
  // 0–1000 m, everything else 0–100 m. (The flight this replaced climbed in the north-east
  // whatever the heights.)
  FullTree t(5);
  for (NodeRecord& n : t.nodes) {
    const uint32_t shift = 4u - n.level;
    if (n.x >= (11u >> shift) && n.y <= (4u >> shift)) n.maxZ = 1000.0f;
  }
  t.header.extentMax[2] = 1000.0;
  const ChunkTree tree = t.tree();
  const ReliefGrid g = reliefGrid(tree);
  EXPECT_EQ(g.columns, 16);
  EXPECT_EQ(g.rows, 16);
  EXPECT_EQ(g.range[size_t(2 * 16 + 12)], 1000.0);
  EXPECT_EQ(g.range[size_t(12 * 16 + 2)], 100.0);
  const Flight f = autoFlight(tree, 320, 240, 60.0);
  ASSERT_GT(f.climbStart, 10);
  // The climb starts over the rugged corner, which the low pass flew towards from the
  // north-west, looking at it.
  const glm::dvec3 top = f.keyframes[size_t(f.climbStart)].eye;
  EXPECT_GT(top.x, 0.65 * 1024);
  EXPECT_LT(top.y, 0.35 * 1024);
  EXPECT_LT(f.keyframes.front().eye.x, 0.15 * 1024);
  EXPECT_GT(f.keyframes.front().eye.y, 0.85 * 1024);
  const glm::dvec3 look = f.keyframes.front().target - f.keyframes.front().eye;
  EXPECT_GT(look.x, 0.0);
  EXPECT_LT(look.y, 0.0);
  // Deterministic.
  const Flight again = autoFlight(tree, 320, 240, 60.0);
  ASSERT_EQ(again.keyframes.size(), f.keyframes.size());
  EXPECT_EQ(again.keyframes.back().eye, f.keyframes.back().eye);
}

}  // namespace
}  // namespace terralod
