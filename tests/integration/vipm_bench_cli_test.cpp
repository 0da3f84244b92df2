// `terralod bench --source` on a VIPM tileset measures what the VIPM kind draws: error within
// τ, no holes, no pops with geomorphing (the surface still moves between frames: the morph
// step), pops without (`--no-morph`), and the VIPM figures (vertices drawn, decode and
// reconstruction time per chunk, material pops).

#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>

#include "cli_runner.h"
#include "shared_directory.h"

namespace terralod::test {
namespace {

class VipmBenchCli : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    sDir = new TempDir;
    sTileset = new SharedDirectory(
        sharedDirectory("crater-vipm", programStamp(TERRALOD_CLI), [](const std::string& dir) {
          const RunResult built = runTerralod(
              {"build", testData("crater_lake_0513.bt"), "--kind", "vipm", "-o", dir + "/c.tlod"});
          return built.exitCode == 0 ? std::string() : built.err;
        }));
    ASSERT_EQ(sTileset->error, "");
    // Down towards the south-west rim.
    std::ofstream(sDir->file("descend.json")) << R"({"fov_deg": 60, "size": [320, 240],
      "frames": 40, "keyframes": [
        {"eye": [5000, -2000, 6000], "target": [7500, 8000, 1900]},
        {"eye": [5000, 1000, 3500], "target": [7500, 8000, 1900]},
        {"eye": [5200, 2500, 2700], "target": [7500, 8000, 1900]}]})";
    // Low over the south-west rim, coming down: leaves draw near, roots further away.
    std::ofstream(sDir->file("low.json")) << R"({"fov_deg": 60, "size": [160, 120],
      "frames": 24, "keyframes": [
        {"eye": [5200, 2500, 2600], "target": [7500, 8000, 1900]},
        {"eye": [5200, 2500, 2600], "target": [7500, 8000, 1900]},
        {"eye": [5400, 3500, 2350], "target": [7500, 8000, 1900]}]})";
    // Hovering: the same camera every frame, so the LOD never changes.
    std::ofstream(sDir->file("hover.json")) << R"({"fov_deg": 60, "size": [160, 120],
      "frames": 16, "keyframes": [
        {"eye": [5200, 2500, 2700], "target": [7500, 8000, 1900]},
        {"eye": [5200, 2500, 2700], "target": [7500, 8000, 1900]}]})";
  }
  static void TearDownTestSuite() {
    delete sDir;
    delete sTileset;
    delete sNoRules;
    delete sLeaves;
    delete sLeavesNoRules;
  }

  // The tilesets only the material test reads (built by the test that needs them, so the
  // other starts at once).
  static void buildMaterialTilesets() {
    sNoRules = new SharedDirectory(sharedDirectory(
        "crater-vipm-no-rules", programStamp(TERRALOD_CLI), [](const std::string& dir) {
          const RunResult built =
              runTerralod({"build", testData("crater_lake_0513.bt"), "--kind", "vipm",
                           "--no-material-rules", "-o", dir + "/c.tlod"});
          return built.exitCode == 0 ? std::string() : built.err;
        }));
    ASSERT_EQ(sNoRules->error, "");
    // Leaves as far as the rules allow (no blot roots, which are built without the rules in
    // both): what the rules do to material boundaries, alone.
    for (const auto& [shared, rules] :
         {std::pair{&sLeaves, "rules"}, std::pair{&sLeavesNoRules, "no-rules"}}) {
      *shared = new SharedDirectory(sharedDirectory(
          std::string("crater-vipm-leaves-") + rules, programStamp(TERRALOD_CLI),
          [rules](const std::string& dir) {
            std::vector<std::string> args = {"build",        testData("crater_lake_0513.bt"),
                                             "--kind",       "vipm",
                                             "--blot-error", "off",
                                             "-o",           dir + "/c.tlod"};
            if (std::string(rules) == "no-rules") args.push_back("--no-material-rules");
            const RunResult built = runTerralod(args);
            return built.exitCode == 0 ? std::string() : built.err;
          }));
      ASSERT_EQ((*shared)->error, "");
    }
  }

  // (With --warm-start: the first camera's chunks load before the first frame, so every frame
  // is measured, however fast the loader threads run beside the drawing.)
  static nlohmann::json bench(const std::vector<std::string>& extra) {
    std::vector<std::string> args = {
        "bench",       sTileset->file("c.tlod"),        "--flight", sDir->file("descend.json"),
        "--source",    testData("crater_lake_0513.bt"), "--json",   sDir->file("b.json"),
        "--warm-start"};
    args.insert(args.end(), extra.begin(), extra.end());
    const RunResult r = runTerralod(args);
    EXPECT_EQ(r.exitCode, 0) << r.err;
    return nlohmann::json::parse(readWholeFile(sDir->file("b.json")));
  }

  // Material pops (quality figures: with --source).
  static nlohmann::json materials(const SharedDirectory& tileset, const std::string& flight,
                                  const std::vector<std::string>& extra) {
    std::vector<std::string> args = {
        "bench",       tileset.file("c.tlod"),          "--flight", sDir->file(flight),
        "--source",    testData("crater_lake_0513.bt"), "--json",   sDir->file("m.json"),
        "--warm-start"};
    args.insert(args.end(), extra.begin(), extra.end());
    const RunResult r = runTerralod(args);
    EXPECT_EQ(r.exitCode, 0) << r.err;
    return nlohmann::json::parse(readWholeFile(sDir->file("m.json")));
  }

  static inline TempDir* sDir = nullptr;
  static inline SharedDirectory* sTileset = nullptr;
  static inline SharedDirectory* sNoRules = nullptr;
  static inline SharedDirectory* sLeaves = nullptr;
  static inline SharedDirectory* sLeavesNoRules = nullptr;
};

TEST_F(VipmBenchCli, MeasuresTheDrawnSurfaceAndReportsVipmFigures) {
  const auto morphed = bench({});
  for (const char* key :
       {"max_error_px", "max_pop_px", "max_morph_step_px", "holes_total", "vertices_p50",
        "reconstruct_ms_p50", "reconstruct_ms_max", "material_pop_px", "material_pop_px_p99",
        "material_pop_px_mean", "material_pop_frames", "material_morph_step_px"})
    ASSERT_TRUE(morphed.contains(key)) << key;
  EXPECT_GT(morphed["max_error_px"].get<double>(), 0.0);
  EXPECT_LE(morphed["max_error_px"].get<double>(), 2.0);  // τ
  EXPECT_EQ(morphed["holes_total"], 0);
  EXPECT_GT(morphed["max_morph_step_px"].get<double>(), morphed["max_pop_px"].get<double>());
  EXPECT_GT(morphed["vertices_p50"].get<double>(), 100.0);
  EXPECT_LT(morphed["vertices_p50"].get<double>(), morphed["triangles_p50"].get<double>());
  EXPECT_GT(morphed["reconstruct_ms_p50"].get<double>(), 0.0);
  EXPECT_GE(morphed["reconstruct_ms_max"].get<double>(),
            morphed["reconstruct_ms_p50"].get<double>());
  // The super-chunk blocks' memory beyond their chunks' (outside the budget): some, since a
  // block makes all 16 texture layers with its first chunk, but a small part of the chunks'.
  EXPECT_GT(morphed["block_spare_mb_max"].get<double>(), 0.0);
  EXPECT_LT(morphed["block_spare_mb_max"].get<double>(),
            0.25 * morphed["resident_mb_max"].get<double>());

  const auto unmorphed = bench({"--no-morph"});
  EXPECT_LE(unmorphed["max_error_px"].get<double>(), 2.0);
  EXPECT_GT(unmorphed["max_pop_px"].get<double>(), 0.5);
  // Geomorphing leaves no pop of its own, however fast the descent (2 % of the height a
  // frame): last frame's collapses carry on to this frame's θ. (The measure used to cut short
  // the collapses entering or leaving the geomorph within a step: up to a quarter of the
  // pops without geomorphing here.) The roots keep their children's seams: no merge pops.
  EXPECT_LT(morphed["max_pop_px"].get<double>(), 0.01);
}

TEST_F(VipmBenchCli, CountsPixelsWhoseMaterialChangesWithTheLevel) {
  buildMaterialTilesets();
  if (HasFatalFailure()) return;
  // Leaves only, coming down (the first half of the descent: collapses cross material
  // boundaries in every frame). Without the rules, a collapse's vertex keeps its own material
  // until the collapse is applied: boundaries jump even while geomorphing.
  const std::vector<std::string> half = {"--frames", "20"};
  const auto popping = materials(*sLeavesNoRules, "descend.json", half);
  ASSERT_TRUE(popping.contains("material_pop_px"));
  EXPECT_GE(popping["material_pop_frames"].get<double>(), 5.0);
  EXPECT_GT(popping["material_pop_px"].get<double>(), 100.0);
  EXPECT_GE(popping["material_pop_px"].get<double>(), popping["material_pop_px_p99"].get<double>());
  EXPECT_LE(popping["material_pop_px"].get<double>(), 320.0 * 240.0);
  // With the rules, boundaries stay put: far fewer pixels change material.
  const auto kept = materials(*sLeaves, "descend.json", half);
  EXPECT_GE(kept["material_pop_frames"].get<double>(), 5.0);
  EXPECT_LT(kept["material_pop_px"].get<double>() * 20.0, popping["material_pop_px"].get<double>());
  // Low over the rim with the blot roots further away: they are built without the rules, and
  // fade their materials as they geomorph; without geomorphing they change them at once.
  const auto fading = materials(*sTileset, "low.json", {});
  const auto unmorphed = materials(*sTileset, "low.json", {"--no-morph"});
  EXPECT_GE(fading["material_pop_frames"].get<double>(), 5.0);
  EXPECT_GT(unmorphed["material_pop_px"].get<double>(),
            5.0 * fading["material_pop_px"].get<double>());
  // The same camera every frame: the level never changes, no pixel changes material.
  const auto hovering = materials(*sNoRules, "hover.json", {"--no-morph"});
  EXPECT_GE(hovering["material_pop_frames"].get<double>(), 5.0);
  EXPECT_EQ(hovering["material_pop_px"].get<double>(), 0.0);
}

}  // namespace
}  // namespace terralod::test
