// `terralod bench --edit-script`: strokes applied during a flight are regenerated on a worker
// thread and swapped into the drawn tileset while frames go on; bench reports how long each
// took to be drawn, and no frame waited.

#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>

#include "cli_expectations.h"
#include "cli_runner.h"

namespace terralod::test {
namespace {

class VipmBenchEditCli : public ::testing::Test {
 protected:
  void SetUp() override {
    // With levels above the roots, which a stroke remakes after its leaves and roots.
    const RunResult built = runTerralod({"build", kEditBenchDem, "--kind", "vipm", "--upper-levels",
                                         "auto", "--threads", "2", "-o", mTileset});
    ASSERT_EQ(built.exitCode, 0) << built.err;
    // Down towards the south-west rim, and strokes where it looks: one over 4 x 4 leaves,
    // then one inside a leaf (each starts once the one before is drawn, so the flight is long
    // enough for both with room to spare on a busy machine).
    std::ofstream(mDir.file("descend.json")) << R"({"fov_deg": 60, "size": [320, 240],
      "frames": 120, "keyframes": [
        {"eye": [5000, -2000, 6000], "target": [7500, 8000, 1900]},
        {"eye": [5200, 2500, 2700], "target": [7500, 8000, 1900]}]})";
    std::ofstream(mDir.file("strokes.json")) << R"({"edits": [
        {"brush": "lower", "center": [5156, 6976], "radius": 2000, "amount": 20},
        {"brush": "raise", "center": [7300, 7800], "radius": 300, "amount": 30}]})";
  }
  const std::string kEditBenchDem = testData("crater_lake_0513.bt");
  TempDir mDir;
  const std::string mTileset = mDir.file("c.tlod");
};

TEST_F(VipmBenchEditCli, StrokesDuringAFlightAreSwappedInAndNoFrameWaits) {
  const RunResult r = runTerralod({"bench", mTileset, "--flight", mDir.file("descend.json"),
                                   "--edit-script", mDir.file("strokes.json"), "--edit-every", "10",
                                   "--edit-source", kEditBenchDem, "--json", mDir.file("b.json")});
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const auto j = nlohmann::json::parse(std::ifstream(mDir.file("b.json")));
  EXPECT_EQ(j["edit_strokes"], 2);
  EXPECT_EQ(j["edit_swapped"], 2) << j.dump(2);
  EXPECT_GE(j["edit_nodes_max"].get<double>(), 20.0);  // 16 leaves and their roots, at least
  EXPECT_GE(j["edit_nodes_p50"].get<double>(), 2.0);   // a leaf and its root
  // The flight looks at them: the scene had drawn chunks to swap (not only files to change).
  EXPECT_GE(j["edit_resident_nodes_max"].get<double>(), 1.0);
  EXPECT_GT(j["edit_regen_ms_p50"].get<double>(), 0.0);
  EXPECT_GE(j["edit_latency_ms_p50"].get<double>(), j["edit_regen_ms_p50"].get<double>());
  // Meanwhile the large stroke's chunks were drawn as their whole grids, well before they were
  // made (about 80 against 600 ms here; the small one's are made within a few frames, and
  // its whole grids may not be drawn before that).
  EXPECT_GE(j["edit_interim_drawn"].get<int>(), 1) << j.dump(2);
  EXPECT_LT(j["edit_interim_latency_ms_max"].get<double>(), j["edit_latency_ms_max"].get<double>());
  // The nodes above the roots came after the leaves and roots were drawn.
  EXPECT_EQ(j["edit_upper_strokes"], 2) << j.dump(2);
  EXPECT_GT(j["edit_upper_ms_p50"].get<double>(), j["edit_regen_ms_p50"].get<double>());
  EXPECT_GE(j["edit_upper_nodes_p50"].get<double>(), 1.0);
  EXPECT_EQ(j["frames_waiting_on_io"], 0);
  EXPECT_EQ(j["load_failures"], 0);
}

TEST_F(VipmBenchEditCli, EditsDuringAFlightAreRefusedWhereTheyCannotWork) {
  const std::vector<std::string> bench = {"bench",         mTileset,
                                          "--flight",      mDir.file("descend.json"),
                                          "--json",        mDir.file("b.json"),
                                          "--edit-script", mDir.file("strokes.json")};
  auto with = [&](std::vector<std::string> extra) {
    std::vector<std::string> args = bench;
    args.insert(args.end(), extra.begin(), extra.end());
    return runTerralod(args);
  };
  expectOneErrorLine(with({"--source", kEditBenchDem}),
                     "--edit-script and --source exclude each other");
  // The tileset's source (crater_lake_0513.bt) is neither beside it nor here.
  expectOneErrorLine(with({}), "edit needs the source's full-resolution heights");
  const std::string fixed = mDir.file("static.tlod");
  ASSERT_EQ(runTerralod({"build", kEditBenchDem, "--threads", "2", "-o", fixed}).exitCode, 0);
  expectOneErrorLine(runTerralod({"bench", fixed, "--flight", mDir.file("descend.json"), "--json",
                                  mDir.file("b.json"), "--edit-script", mDir.file("strokes.json"),
                                  "--edit-source", kEditBenchDem}),
                     fixed + ": is not a VIPM tileset");
}

}  // namespace
}  // namespace terralod::test
