// `terralod build --mesher greedy`: under 0.6x RTIN's triangles at every level of Crater Lake
// (the levels above the blocks meshed top down when the raster is read whole, RTIN kept where
// it is the smaller mesh), a tileset `verify` passes (the parent's bound while geomorphing,
// the fully morphed surface within the recorded gap of the parent's), and a flight that draws
// it within τ, without holes, popping by at most the gap (a fraction of τ) where RTIN chunks
// pop by nothing; rasters of any size.

#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>

#include "cli_runner.h"

namespace terralod::test {
namespace {

class GreedyMesherCli : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    sDir = new TempDir;
    for (const char* mesher : {"rtin", "greedy"}) {
      const RunResult r = runTerralod({"build", testData("crater_lake_0513.bt"), "--no-texture",
                                       "--mesher", mesher, "-o", tileset(mesher)});
      ASSERT_EQ(r.exitCode, 0) << r.err;
    }
    // Down towards the south-west rim: every level splits on the way.
    std::ofstream(sDir->file("descend.json")) << R"({"fov_deg": 60, "size": [320, 240],
      "frames": 48, "keyframes": [
        {"eye": [5000, -2000, 6000], "target": [7500, 8000, 1900]},
        {"eye": [5000, 1000, 3500], "target": [7500, 8000, 1900]},
        {"eye": [5200, 2500, 2700], "target": [7500, 8000, 1900]}]})";
  }
  static void TearDownTestSuite() {
    delete sDir;
    sDir = nullptr;
  }
  static std::string tileset(const std::string& mesher) { return sDir->file(mesher + ".tlod"); }
  static nlohmann::json perLevel(const std::string& mesher) {
    const RunResult r = runTerralod({"info", tileset(mesher), "--json"});
    EXPECT_EQ(r.exitCode, 0) << r.err;
    return nlohmann::json::parse(r.out)["per_level"];
  }
  static nlohmann::json bench(const std::string& mesher) {
    const RunResult r = runTerralod(
        {"bench", tileset(mesher), "--flight", sDir->file("descend.json"), "--tau", "1", "--source",
         testData("crater_lake_0513.bt"), "--json", sDir->file(mesher + ".json")});
    EXPECT_EQ(r.exitCode, 0) << r.err;
    return nlohmann::json::parse(readWholeFile(sDir->file(mesher + ".json")));
  }
  static inline TempDir* sDir = nullptr;
};

TEST_F(GreedyMesherCli, FewerTrianglesAtEveryLevelAndVerified) {
  const nlohmann::json rtin = perLevel("rtin"), greedy = perLevel("greedy");
  ASSERT_EQ(rtin.size(), 4u);
  ASSERT_EQ(greedy.size(), 4u);
  // The 512-cell root is the block level and the build read the raster whole, so the root is
  // greedy too, and every level holds the issue's goal: at most 0.6x RTIN's triangles (0.21,
  // 0.32, 0.40 and 0.43x; without the collapses after insertion 0.53, 0.55, 0.605, 0.616x at
  // session 66).
  for (size_t l = 0; l < 4; ++l)
    EXPECT_LT(greedy[l]["triangles"].get<double>(), 0.6 * rtin[l]["triangles"].get<double>())
        << "level " << l;
  const RunResult v =
      runTerralod({"verify", tileset("greedy"), "--source", testData("crater_lake_0513.bt")});
  EXPECT_EQ(v.exitCode, 0) << v.out << v.err;
  EXPECT_TRUE(has(v.out, "plus 0.125 x the parent level's bound")) << v.out;
  const RunResult info = runTerralod({"info", tileset("greedy"), "--json"});
  EXPECT_TRUE(has(info.out, "\"mesher\": \"greedy\"")) << info.out;
}

// With 128-cell blocks the levels at and above them (0-2) are meshed first, top down, from
// every height: the root takes insertion (well under RTIN's triangles), its descendants
// follow it, and every chunk comes out as the 512-cell-block build makes it, where the block
// tasks mesh levels 1-2 from the same root.
TEST_F(GreedyMesherCli, LevelsAboveTheBlocksAreMeshedTopDown) {
  const std::string small = sDir->file("blocks128.tlod");
  const RunResult b = runTerralod({"build", testData("crater_lake_0513.bt"), "--no-texture",
                                   "--mesher", "greedy", "--block-cells", "128", "-o", small});
  ASSERT_EQ(b.exitCode, 0) << b.err;
  const RunResult r = runTerralod({"info", small, "--json"});
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const nlohmann::json levels = nlohmann::json::parse(r.out)["per_level"];
  const nlohmann::json greedy = perLevel("greedy"), rtin = perLevel("rtin");
  ASSERT_EQ(levels.size(), 4u);
  for (size_t l = 0; l < 4; ++l) {
    EXPECT_EQ(levels[l]["triangles"], greedy[l]["triangles"]) << "level " << l;
    EXPECT_EQ(levels[l]["bytes"], greedy[l]["bytes"]) << "level " << l;
  }
  EXPECT_LT(levels[0]["triangles"].get<double>(), 0.6 * rtin[0]["triangles"].get<double>());
  const RunResult v = runTerralod({"verify", small, "--source", testData("crater_lake_0513.bt")});
  EXPECT_EQ(v.exitCode, 0) << v.out << v.err;
}

// On smooth ground (the 1 m synth, 128-cell leaves) the coarse levels hold a few dozen
// triangles. A greedy chunk keeps no lines for its descendants (each starts from its parent's
// vertices), so it is not held to two triangles per leaf square: the root takes 3 triangles
// where the bintree takes 14 (before, with the leaf squares, RTIN's 14 and 28 were kept at
// levels 0-1). The leaves pay for it: their parent's edges cross their borders off the grid,
// and following them within the gap costs about as many triangles as the bintree's.
TEST_F(GreedyMesherCli, CoarseLevelsAreNotHeldToTheLeafSquares) {
  const std::string dem = sDir->file("smooth.tif");
  ASSERT_EQ(
      runTerralod({"synth", "--size", "1025", "--spacing", "1", "--seed", "1", "-o", dem}).exitCode,
      0);
  auto levels = [&](const std::string& mesher) {
    const std::string out = sDir->file("smooth-" + mesher + ".tlod");
    const RunResult b = runTerralod({"build", dem, "--no-texture", "--mesher", mesher, "-o", out});
    EXPECT_EQ(b.exitCode, 0) << b.err;
    const RunResult r = runTerralod({"info", out, "--json"});
    EXPECT_EQ(r.exitCode, 0) << r.err;
    return nlohmann::json::parse(r.out)["per_level"];
  };
  const nlohmann::json rtin = levels("rtin"), greedy = levels("greedy");
  ASSERT_EQ(greedy.size(), 4u);  // a 1024-cell root, 512-cell blocks, 128-cell leaves
  double greedyTotal = 0, rtinTotal = 0;
  for (size_t l = 0; l < 4; ++l) {
    const double g = greedy[l]["triangles"].get<double>(), r = rtin[l]["triangles"].get<double>();
    if (l < 2) {
      EXPECT_LT(g, 0.6 * r) << "level " << l;  // 3 against 14, 15 against 28
    }
    greedyTotal += g;
    rtinTotal += r;
  }
  EXPECT_LT(greedyTotal, 0.95 * rtinTotal);  // 284 against 313
  const RunResult v = runTerralod({"verify", sDir->file("smooth-greedy.tlod"), "--source", dem});
  EXPECT_EQ(v.exitCode, 0) << v.out << v.err;
}

// A streamed build keeps only sparse heights for the levels at and above the blocks, which
// greedy insertion cannot scan: its root stays RTIN (as many triangles as the RTIN build's),
// the levels below start from it, and it verifies.
TEST_F(GreedyMesherCli, AStreamedBuildKeepsItsRootRtin) {
  const std::string streamed = sDir->file("streamed.tlod");
  const RunResult b = runTerralod({"build", testData("crater_lake_0513.bt"), "--no-texture",
                                   "--mesher", "greedy", "--memory-mb", "1", "-o", streamed});
  ASSERT_EQ(b.exitCode, 0) << b.err;
  ASSERT_TRUE(has(b.err + b.out, "streamed")) << b.err << b.out;
  const RunResult r = runTerralod({"info", streamed, "--json"});
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const nlohmann::json levels = nlohmann::json::parse(r.out)["per_level"], rtin = perLevel("rtin");
  EXPECT_EQ(levels[0]["triangles"], rtin[0]["triangles"]);
  EXPECT_LT(levels[3]["triangles"].get<double>(), 0.7 * rtin[3]["triangles"].get<double>());
  const RunResult v =
      runTerralod({"verify", streamed, "--source", testData("crater_lake_0513.bt")});
  EXPECT_EQ(v.exitCode, 0) << v.out << v.err;
}

// Rasters whose sides are not a power of two plus one: the RTIN level above the greedy ones
// clips its triangles at the data's last row and column and fans what is left, with edges of any
// slope (this failed with "has a vertex without a height" on both rasters, and on the bundled
// New Zealand DEM, when greedy chunks cut their parent's triangles along lines).
TEST_F(GreedyMesherCli, RastersOfAnySizeBuildAndVerify) {
  for (const char* size : {"301", "2003"}) {
    const std::string dem = sDir->file(std::string("synth") + size + ".tif");
    ASSERT_EQ(
        runTerralod({"synth", "--size", size, "--spacing", "5", "--seed", "1", "-o", dem}).exitCode,
        0);
    const std::string out = sDir->file(std::string("synth") + size + ".tlod");
    const RunResult r =
        runTerralod({"build", dem, "--no-texture", "--mesher", "greedy", "-o", out});
    ASSERT_EQ(r.exitCode, 0) << size << ": " << r.err;
    const RunResult v = runTerralod({"verify", out, "--source", dem});
    EXPECT_EQ(v.exitCode, 0) << size << ": " << v.out << v.err;
  }
}

TEST_F(GreedyMesherCli, FlightsStayWithinTauAndPopByAtMostTheGap) {
  const nlohmann::json rtin = bench("rtin"), greedy = bench("greedy");
  for (const nlohmann::json* b : {&rtin, &greedy}) {
    EXPECT_LE((*b)["max_error_px"].get<double>(), 1.0);  // τ
    EXPECT_EQ((*b)["holes_total"], 0);
    EXPECT_LT((*b)["image_pop_mean"].get<double>(), 0.5);  // of 255
  }
  EXPECT_LT(greedy["triangles_p50"].get<double>(), 0.85 * rtin["triangles_p50"].get<double>());
  // RTIN children start as their parent exactly; greedy ones within 1/8 of its error, which
  // the split makes τ pixels: a pop of at most τ/8 (plus rounding), and some.
  EXPECT_LT(rtin["max_pop_px"].get<double>(), 0.02);
  EXPECT_GT(greedy["max_pop_px"].get<double>(), rtin["max_pop_px"].get<double>());
  EXPECT_LE(greedy["max_pop_px"].get<double>(), 0.125 * 1.0 + 0.02);
}

}  // namespace
}  // namespace terralod::test
