// terralod vegetation: a quick bake (small LDIs, one ray a pixel), then info, points and
// render-tile on it, from a file and over HTTP from a real nginx; and bad input.

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "cli_runner.h"
#include "nginx_server.h"
#include "terralod/render/image.h"

namespace terralod::test {
namespace {

namespace fs = std::filesystem;

// One quick meadow bake shared by the tests (about a second).
const fs::path& quickMeadow() {
  static TempDir dir;
  static const fs::path file = [] {
    const fs::path f = dir.path() / "meadow.tlv";
    const RunResult r =
        runTerralod({"vegetation", "bake", "--scene", "meadow", "--finest", "48",
                     "--rays-per-pixel", "1", "--occlusion-rays", "2", "-o", f.string()});
    EXPECT_EQ(r.exitCode, 0) << r.err;
    return f;
  }();
  return file;
}

std::vector<std::vector<std::string>> readCsv(const fs::path& path) {
  std::vector<std::vector<std::string>> rows;
  std::istringstream in(readWholeFile(path.string()));
  for (std::string line; std::getline(in, line);) {
    std::vector<std::string> cells;
    std::istringstream l(line);
    for (std::string c; std::getline(l, c, ',');) cells.push_back(c);
    rows.push_back(cells);
  }
  return rows;
}

TEST(VegetationCli, InfoDescribesTheTilesAndEveryLdi) {
  const RunResult r = runTerralod({"vegetation", "info", quickMeadow().string(), "--json"});
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["scene"], "meadow");
  EXPECT_EQ(j["ldis"], 448);
  EXPECT_EQ(j["tiles"].size(), 8u);
  EXPECT_EQ(j["resolutions"].size(), 7u);
  EXPECT_EQ(j["resolutions"][0]["resolution"], 48);
  EXPECT_GT(j["plants"].get<int>(), 8 * 50);
  EXPECT_GT(j["triangles_modelled"].get<int>(), 8 * 20000);
  EXPECT_GT(j["depth_pixels"].get<int>(), 0);
  EXPECT_EQ(j["file_bytes"].get<uint64_t>(), fs::file_size(quickMeadow()));
  for (const auto& t : j["tiles"])
    EXPECT_EQ(t["species"].size(), 3u);  // grass, dandelions, flowers
}

TEST(VegetationCli, PointsListEveryPlantAndTileOfATilingWhoseEdgesMatch) {
  TempDir dir;
  const fs::path points = dir.path() / "p.csv", tiles = dir.path() / "t.csv";
  const RunResult r =
      runTerralod({"vegetation", "points", quickMeadow().string(), "--tiling", "12x9", "--seed",
                   "4", "--csv", points.string(), "--tiles-csv", tiles.string()});
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_NE(r.out.find("overlaps: tight 0, packing 0"), std::string::npos) << r.out;
  const auto t = readCsv(tiles);
  ASSERT_EQ(t.size(), 1u + 12 * 9);
  EXPECT_EQ(t[0], (std::vector<std::string>{"tile_x", "tile_y", "prototile", "north", "east",
                                            "south", "west"}));
  std::map<std::pair<int, int>, std::vector<int>> at;
  for (size_t i = 1; i < t.size(); ++i)
    at[{std::stoi(t[i][0]), std::stoi(t[i][1])}] = {std::stoi(t[i][3]), std::stoi(t[i][4]),
                                                    std::stoi(t[i][5]), std::stoi(t[i][6])};
  for (auto& [xy, e] : at) {
    const auto east = at.find({xy.first + 1, xy.second}),
               north = at.find({xy.first, xy.second + 1});
    if (east != at.end()) {
      EXPECT_EQ(e[1], east->second[3]);
    }
    if (north != at.end()) {
      EXPECT_EQ(e[0], north->second[2]);
    }
  }
  const auto p = readCsv(points);
  ASSERT_GT(p.size(), 12u * 9u * 50u);
  EXPECT_EQ(p[0], (std::vector<std::string>{"x", "y", "tight_radius", "packing_radius", "species",
                                            "version", "tile_x", "tile_y"}));
  for (size_t i = 1; i < p.size(); ++i) {  // each plant lies in the tile it names
    const double x = std::stod(p[i][0]) / 2.0, y = std::stod(p[i][1]) / 2.0;
    ASSERT_EQ(int(x), std::stoi(p[i][6]));
    ASSERT_EQ(int(y), std::stoi(p[i][7]));
  }
}

TEST(VegetationCli, RenderTileDrawsAnLdiAtItsResolutionAndTheTileFromAbove) {
  TempDir dir;
  const fs::path ldi = dir.path() / "ldi.png", top = dir.path() / "top.png";
  RunResult r = runTerralod({"vegetation", "render-tile", quickMeadow().string(), "--tile", "3",
                             "--resolution", "0", "--direction", "5", "-o", ldi.string()});
  ASSERT_EQ(r.exitCode, 0) << r.err;
  auto image = readPng(ldi.string());
  ASSERT_TRUE(image) << image.error().message;
  EXPECT_EQ(std::max(image->width, image->height), 48);
  r = runTerralod({"vegetation", "render-tile", quickMeadow().string(), "--tile", "3", "--view",
                   "top", "-o", top.string()});
  ASSERT_EQ(r.exitCode, 0) << r.err;
  image = readPng(top.string());
  ASSERT_TRUE(image);
  EXPECT_EQ(image->width, 72);  // 48 pixels a tile and a quarter tile each side
  // Plants cover some of the soil: not every pixel is the soil's colour.
  int soil = 0;
  for (int y = 0; y < image->height; ++y)
    for (int x = 0; x < image->width; ++x) soil += image->pixel(x, y)[0] == 92;
  EXPECT_LT(soil, image->width * image->height * 95 / 100);
}

TEST(VegetationCli, ReadsTheFileByRangesOverHttp) {
  TempDir dir;
  fs::copy_file(quickMeadow(), dir.path() / "m.tlv");
  NginxServer server(dir.path());
  const RunResult local = runTerralod({"vegetation", "info", quickMeadow().string()});
  const RunResult remote = runTerralod({"vegetation", "info", server.url("m.tlv")});
  ASSERT_EQ(remote.exitCode, 0) << remote.err;
  // The same description but for the name.
  const std::string after = ": vegetation scene";
  ASSERT_NE(local.out.find(after), std::string::npos);
  EXPECT_EQ(remote.out.substr(remote.out.find(after)), local.out.substr(local.out.find(after)));
  const fs::path png = dir.path() / "r.png";
  const RunResult r = runTerralod({"vegetation", "render-tile", server.url("m.tlv"), "--tile", "1",
                                   "--resolution", "2", "-o", png.string()});
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_TRUE(fs::exists(png));
}

// "edges 0.693 (62%)" -> 62
double percentAfter(const std::string& out, const std::string& label) {
  const size_t at = out.find(label);
  EXPECT_NE(at, std::string::npos) << out;
  const size_t open = out.find('(', at);
  return std::stod(out.substr(open + 1));
}

TEST(VegetationCli, PlacingEdgesFirstFillsTheRimThePaperLeavesSparse) {
  const std::vector<std::string> args = {"vegetation", "placement", "--scene",  "sunflowers",
                                         "--seeds",    "4",         "--tiling", "16x16",
                                         "--band",     "0.25"};
  const RunResult ours = runTerralod(args);
  std::vector<std::string> plainArgs = args;
  plainArgs.push_back("--plain");
  const RunResult plain = runTerralod(plainArgs);
  ASSERT_EQ(ours.exitCode, 0) << ours.err;
  ASSERT_EQ(plain.exitCode, 0) << plain.err;
  EXPECT_NE(ours.out.find("overlaps: tight 0, packing 0"), std::string::npos) << ours.out;
  // Within a quarter metre of the edges: the plain round-robin leaves a sparse line.
  EXPECT_LT(percentAfter(plain.out, "edges"), 80) << plain.out;
  EXPECT_GT(percentAfter(ours.out, "edges"), 90) << ours.out;
}

TEST(VegetationCli, TilingShowsNoStructureWhereTheHierarchicalOneIsPlaid) {
  TempDir dir;
  const fs::path png = dir.path() / "fig4.png";
  const RunResult r =
      runTerralod({"vegetation", "tiling", "--size", "64", "--json", "-o", png.string()});
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  EXPECT_LT(j["stochastic_wang"]["autocorrelation_max_off_origin"].get<double>(), 0.1);
  EXPECT_GT(j["robinson_style_hierarchical"]["autocorrelation_mean_on_axes"].get<double>(), 0.1);
  EXPECT_NEAR(j["stochastic_wang"]["same_east"].get<double>(), 0.125, 0.03);
  EXPECT_TRUE(readPng(png.string()));
}

TEST(VegetationCli, BadInputGetsOneLineAndWritesNothing) {
  TempDir dir;
  const fs::path junk = dir.path() / "junk.tlv";
  { std::ofstream(junk) << "not a vegetation file at all"; }
  struct Case {
    std::vector<std::string> args;
    std::string says;
  };
  const std::string out = (dir.path() / "out.tlv").string();
  const std::vector<Case> cases = {
      {{"vegetation", "info", junk.string()}, "junk.tlv"},
      {{"vegetation", "info", (dir.path() / "missing.tlv").string()}, "missing.tlv"},
      {{"vegetation", "bake", "--scene", "forest", "-o", out}, "unknown scene 'forest'"},
      {{"vegetation", "bake", "--scene", "meadow", "--tile-size", "0.1", "-o", out}, "--tile-size"},
      {{"vegetation", "bake", "--scene", "meadow", "-o",
        (dir.path() / "no/such/dir/v.tlv").string()},
       "v.tlv"},
      {{"vegetation", "points", quickMeadow().string(), "--tiling", "12by9"}, "--tiling"},
      {{"vegetation", "points", quickMeadow().string(), "--tiling", "5000x5000"}, "--tiling"},
      {{"vegetation", "render-tile", quickMeadow().string(), "--tile", "8", "-o",
        (dir.path() / "x.png").string()},
       "--tile"},
      {{"vegetation", "render-tile", quickMeadow().string(), "-o", (dir.path() / "x.gif").string()},
       "x.gif"},
  };
  for (const Case& c : cases) {
    const RunResult r = runTerralod(c.args);
    EXPECT_EQ(r.exitCode, 1) << c.args[1] << " " << c.args.back();
    ASSERT_EQ(r.errLines().size(), 1u) << r.err;
    EXPECT_NE(r.err.find(c.says), std::string::npos) << r.err;
  }
  EXPECT_FALSE(fs::exists(out));
  EXPECT_FALSE(fs::exists(dir.path() / "x.png"));
  // One bad output among several: none is written.
  const std::string points = (dir.path() / "p.csv").string();
  for (const std::vector<std::string>& extra :
       {std::vector<std::string>{"--tiles-csv", (dir.path() / "no/such/t.csv").string()},
        std::vector<std::string>{"--density-png", (dir.path() / "d.gif").string()}}) {
    std::vector<std::string> args = {
        "vegetation", "points", quickMeadow().string(), "--tiling", "4x4", "--csv", points};
    args.insert(args.end(), extra.begin(), extra.end());
    const RunResult r = runTerralod(args);
    EXPECT_EQ(r.exitCode, 1) << extra[0];
    EXPECT_EQ(r.errLines().size(), 1u) << r.err;
    EXPECT_FALSE(fs::exists(points)) << extra[0];
  }
  EXPECT_FALSE(fs::exists(dir.path() / "x.gif"));
}

}  // namespace
}  // namespace terralod::test
