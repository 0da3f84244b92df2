// `terralod bench` measures what it claims: with morphing and skirts a descending flight shows
// no pops and no holes and stays within τ; without morphing the pops appear, without skirts
// the cracks do. (The full flights over every DEM are benchmarks: docs/benchmarks.md.)

#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>

#include "cli_runner.h"
#include "shared_directory.h"

namespace terralod::test {
namespace {

class BenchCli : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    sDir = new TempDir;
    // Built once for every test process of this build of the CLI.
    sTileset = new SharedDirectory(
        sharedDirectory("crater-default", programStamp(TERRALOD_CLI), [](const std::string& dir) {
          const RunResult built =
              runTerralod({"build", testData("crater_lake_0513.bt"), "-o", dir + "/c.tlod"});
          return built.exitCode == 0 ? std::string() : built.err;
        }));
    ASSERT_EQ(sTileset->error, "");
    // Down from 6 km towards the south-west rim, about 1 % of the height per frame.
    std::ofstream(sDir->file("descend.json")) << R"({"fov_deg": 60, "size": [320, 240],
      "frames": 150, "keyframes": [
        {"eye": [5000, -2000, 6000], "target": [7500, 8000, 1900]},
        {"eye": [5000, 1000, 3500], "target": [7500, 8000, 1900]},
        {"eye": [5200, 2500, 2700], "target": [7500, 8000, 1900]}]})";
  }
  static void TearDownTestSuite() {
    delete sDir;
    delete sTileset;
  }

  static nlohmann::json bench(const std::string& tau, const std::vector<std::string>& extra) {
    std::vector<std::string> args = {"bench",    sTileset->file("c.tlod"),
                                     "--flight", sDir->file("descend.json"),
                                     "--source", testData("crater_lake_0513.bt"),
                                     "--tau",    tau,
                                     "--json",   sDir->file("b.json")};
    args.insert(args.end(), extra.begin(), extra.end());
    const RunResult r = runTerralod(args);
    EXPECT_EQ(r.exitCode, 0) << r.err;
    return nlohmann::json::parse(readWholeFile(sDir->file("b.json")));
  }

  static inline TempDir* sDir = nullptr;
  static inline SharedDirectory* sTileset = nullptr;
};

TEST_F(BenchCli, MorphingAndSkirtsLeaveNoPopsNoHolesAndErrorWithinTau) {
  const auto j = bench("1", {});
  for (const char* key :
       {"frames", "tau", "select_us_p50", "select_us_max", "frame_ms_p50", "frame_ms_p99",
        "triangles_p50", "draws_p50", "max_error_px", "max_pop_px", "holes_total"})
    EXPECT_TRUE(j.contains(key)) << key;
  EXPECT_EQ(j["frames"], 150);
  EXPECT_LE(j["max_error_px"].get<double>(), 1.0);
  EXPECT_GT(j["max_error_px"].get<double>(), 0.0);
  EXPECT_LE(j["max_pop_px"].get<double>(), 0.1);
  EXPECT_EQ(j["holes_total"], 0);
  // Sky, then one multi-draw per pair of texture tile sizes in view (a few).
  EXPECT_LE(j["draws_p50"].get<double>(), 4.0);
  // Lighting and colour come from textures, so LOD changes the picture very little.
  EXPECT_TRUE(j["textured"].get<bool>());
  EXPECT_GT(j["image_pop_frames"].get<int>(), 0);
  EXPECT_LT(j["image_pop_mean"].get<double>(), 0.5);
  EXPECT_TRUE(j.contains("upload_ms_max"));
  EXPECT_FALSE(j.contains("material_pop_px"));  // VIPM tilesets only
}

TEST_F(BenchCli, AWarmStartLoadsTheFirstViewBeforeTheFirstFrame) {
  // From the roots alone the low pass's first frame is drawn coarser (its chunks are asked for
  // only then); with --warm-start the first camera's chunks are loaded first (not a frame)
  // and it shows what it wants. (Later frames depend on how fast the loader threads run
  // beside the drawing: a benchmark's figure, not a test's.)
  auto run = [&](std::vector<std::string> extra) {
    std::vector<std::string> args = {
        "bench",  sTileset->file("c.tlod"), "--auto-flight", "--size", "320x240", "--frames", "1",
        "--json", sDir->file("w.json")};
    args.insert(args.end(), extra.begin(), extra.end());
    const RunResult r = runTerralod(args);
    EXPECT_EQ(r.exitCode, 0) << r.err;
    return nlohmann::json::parse(readWholeFile(sDir->file("w.json")));
  };
  const auto cold = run({});
  EXPECT_EQ(cold["coarser_than_wanted_frames"].get<int>(), 1);
  EXPECT_TRUE(cold["warm_start_ms"].is_null());
  const auto warm = run({"--warm-start"});
  EXPECT_EQ(warm["coarser_than_wanted_frames"].get<int>(), 0);
  EXPECT_GT(warm["warm_start_ms"].get<double>(), 0.0);
  EXPECT_EQ(warm["frames_waiting_on_io"].get<int>(), 0);
}

TEST(BenchTexels, NoTexelCoversMoreThanOnePixelAtTheTexturesTau) {
  // 1 m samples, 1 m leaf error: every level's textures can be sized by eq. 7 for τ = 2
  // (leaves at one texel per sample), so along the climb no texel exceeds a pixel at τ = 2,
  // and at τ = 4 chunks come twice as close and texels reach 2 pixels.
  TempDir dir;
  ASSERT_EQ(
      runTerralod({"synth", "--size", "1025", "--spacing", "1", "-o", dir.file("s.tif")}).exitCode,
      0);
  ASSERT_EQ(runTerralod({"build", dir.file("s.tif"), "--max-error", "1", "-o", dir.file("s.tlod")})
                .exitCode,
            0);
  auto texelsAt = [&](const std::string& tau) {
    const RunResult r =
        runTerralod({"bench", dir.file("s.tlod"), "--auto-flight", "--climb-only", "--size",
                     "320x240", "--tau", tau, "--json", dir.file("b.json")});
    EXPECT_EQ(r.exitCode, 0) << r.err;
    return nlohmann::json::parse(readWholeFile(dir.file("b.json")))["max_texel_per_px"]
        .get<double>();
  };
  EXPECT_LE(texelsAt("2"), 1.0);
  EXPECT_GT(texelsAt("4"), 1.5);
}

TEST_F(BenchCli, WithoutTexturesOneMultiDrawAndNoTexelFigures) {
  const auto j = bench("1", {"--no-textures"});
  EXPECT_EQ(j["draws_p50"], 2.0) << "sky plus one multi-draw";
  EXPECT_FALSE(j.contains("max_texel_per_px"));
  EXPECT_FALSE(j.contains("max_texel_per_px_source_limited"));
  EXPECT_LT(j["image_pop_mean"].get<double>(), 0.5);
}

TEST_F(BenchCli, WithoutMorphingThePopsShow) {
  const auto j = bench("1", {"--no-morph"});
  EXPECT_GE(j["max_pop_px"].get<double>(), 0.25);
}

TEST_F(BenchCli, WithoutSkirtsTheCracksShow) {
  const auto j = bench("0.5", {"--no-skirts"});
  EXPECT_GT(j["holes_total"].get<uint64_t>(), 0u);
}

}  // namespace
}  // namespace terralod::test
