// `build --kind vipm --upper-levels auto`: levels of nodes above the 128-cell roots. The
// tileset verifies (the nodes above the roots at sampled levels, their joins, every flange
// across levels), a far view draws a few large nodes where the flat forest draws every root,
// a flight down from far away draws within τ with no holes, and merges into the nodes above
// the roots do not pop with fans.

#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>
#include <regex>

#include "cli_expectations.h"
#include "cli_runner.h"

namespace terralod::test {
namespace {

const std::string kCrater = testData("crater_lake_0513.bt");

// "wrote X: N chunks, ..." -> N.
int drawnChunks(const std::string& out) {
  std::smatch m;
  return std::regex_search(out, m, std::regex(R"(: (\d+) chunks,)")) ? std::stoi(m[1]) : -1;
}

TEST(VipmUpperLevelsCli, NodesAboveTheRootsVerifyAndDrawTheFarField) {
  TempDir dir;
  const std::string up = dir.file("up.tlod"), flat = dir.file("flat.tlod");
  const RunResult built = runTerralod(
      {"build", kCrater, "--kind", "vipm", "--upper-levels", "auto", "--threads", "2", "-o", up});
  ASSERT_EQ(built.exitCode, 0) << built.err;
  EXPECT_TRUE(has(built.out, "4 levels")) << built.out;
  ASSERT_EQ(
      runTerralod({"build", kCrater, "--kind", "vipm", "--threads", "2", "-o", flat}).exitCode, 0);

  const RunResult verified = runTerralod({"verify", up, "--source", kCrater, "--threads", "2"});
  EXPECT_EQ(verified.exitCode, 0) << verified.out << verified.err;
  EXPECT_TRUE(has(verified.out, "VIPM above the roots: 5 nodes")) << verified.out;
  EXPECT_TRUE(has(verified.out, "5 join exactly their children's coarsest LODs' points"))
      << verified.out;

  // Far away: the four 256-cell nodes (or the top one), not the sixteen roots.
  const std::vector<std::string> far = {
      "--eye", "5000,-30000,20000", "--target", "5000,7000,1800", "--size", "320x240"};
  auto render = [&](const std::string& tileset, const std::string& image) {
    std::vector<std::string> args = {"render", tileset, "-o", dir.file(image)};
    args.insert(args.end(), far.begin(), far.end());
    const RunResult r = runTerralod(args);
    EXPECT_EQ(r.exitCode, 0) << r.err;
    return drawnChunks(r.out);
  };
  const int upper = render(up, "up.png"), roots = render(flat, "flat.png");
  EXPECT_GE(upper, 1);
  EXPECT_LE(upper, 4);
  EXPECT_EQ(roots, 16);

  // Down from far away, through every level: within τ, no holes, no frame waits.
  std::ofstream(dir.file("down.json")) << R"({"fov_deg": 60, "size": [200, 150],
    "frames": 30, "keyframes": [
      {"eye": [5000, -30000, 20000], "target": [7500, 8000, 1900]},
      {"eye": [5000, -5000, 6000], "target": [7500, 8000, 1900]},
      {"eye": [5200, 2500, 2700], "target": [7500, 8000, 1900]}]})";
  for (const char* stitch : {"fans"}) {
    SCOPED_TRACE(stitch);
    const RunResult b = runTerralod({"bench", up, "--flight", dir.file("down.json"), "--source",
                                     kCrater, "--stitch", stitch, "--json", dir.file("b.json")});
    ASSERT_EQ(b.exitCode, 0) << b.err;
    const auto j = nlohmann::json::parse(readWholeFile(dir.file("b.json")));
    EXPECT_LE(j["max_error_px"].get<double>(), 2.0);
    EXPECT_EQ(j["holes_total"].get<int>(), 0);
    EXPECT_EQ(j["frames_waiting_on_io"].get<int>(), 0);
    std::printf("%s: max error %.3f px, max pop %.3f px\n", stitch, j["max_error_px"].get<double>(),
                j["max_pop_px"].get<double>());
  }

  // Down over the rim through two merges into 256-cell nodes (frames 24 and 27). With fans
  // the roots draw exactly the closed seams their parent starts from: no pop. With flanges
  // they keep the T-junctions their parent closes, and the merge moves the surface there.
  std::ofstream(dir.file("rim.json")) << R"({"fov_deg": 60, "size": [320, 240],
    "frames": 60, "keyframes": [
      {"eye": [5000, -2000, 6000], "target": [7500, 8000, 1900]},
      {"eye": [5000, 1000, 3500], "target": [7500, 8000, 1900]},
      {"eye": [5200, 2500, 2700], "target": [7500, 8000, 1900]}]})";
  auto bench = [&](const std::string& tileset, const char* stitch, const char* flight) {
    // (--warm-start: the first camera's chunks load first, so the merges' frames are measured
    // however fast the loader threads run beside the drawing.)
    const RunResult b =
        runTerralod({"bench", tileset, "--flight", dir.file(flight), "--source", kCrater,
                     "--stitch", stitch, "--warm-start", "--json", dir.file("r.json")});
    EXPECT_EQ(b.exitCode, 0) << b.err;
    const auto j = nlohmann::json::parse(readWholeFile(dir.file("r.json")));
    EXPECT_LE(j["max_error_px"].get<double>(), 2.0) << stitch;
    return j;
  };
  // By default (auto) fans on a tileset with nodes above the roots, flanges on a flat forest
  // (whose roots keep their children's seams, so flanges merge without a pop there).
  // (A still camera suffices for the forest's choice; its flights are VipmBenchCli's.)
  std::ofstream(dir.file("still.json")) << R"({"fov_deg": 60, "size": [160, 120],
    "frames": 2, "keyframes": [
      {"eye": [5000, -2000, 6000], "target": [7500, 8000, 1900]},
      {"eye": [5000, -2000, 6000], "target": [7500, 8000, 1900]}]})";
  const auto fans = bench(up, "auto", "rim.json"), flanges = bench(up, "flanges", "rim.json");
  EXPECT_EQ(fans["stitch"], "fans");
  EXPECT_LE(fans["max_pop_px"].get<double>(), 0.1);
  EXPECT_GT(flanges["max_pop_px"].get<double>(), 0.3);
  EXPECT_EQ(bench(flat, "auto", "still.json")["stitch"], "flanges");
}

}  // namespace
}  // namespace terralod::test
