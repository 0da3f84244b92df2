// `terralod bench --report DIR`: a report people can read at a glance, drawn from every frame's
// figures — and the figures in it are the flight's, not made up: the per-frame table adds up to
// the JSON's totals and the plots are real pictures.

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "cli_runner.h"
#include "terralod/render/image.h"

namespace terralod::test {
namespace {

namespace fs = std::filesystem;

// The rows of a CSV file (header first), split at commas.
std::vector<std::vector<std::string>> readCsv(const std::string& path) {
  std::vector<std::vector<std::string>> rows;
  std::istringstream in(readWholeFile(path));
  for (std::string line; std::getline(in, line);) {
    std::vector<std::string> cells;
    std::istringstream cellsIn(line);
    for (std::string cell; std::getline(cellsIn, cell, ',');) cells.push_back(cell);
    rows.push_back(cells);
  }
  return rows;
}

size_t distinctColours(const Image& image) {
  std::set<uint32_t> colours;
  for (size_t i = 0; i + 3 < image.rgba.size(); i += 4)
    colours.insert(uint32_t(image.rgba[i]) << 16 | uint32_t(image.rgba[i + 1]) << 8 |
                   image.rgba[i + 2]);
  return colours.size();
}

class BenchReport : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_EQ(
        runTerralod({"build", testData("crater_lake_0513.bt"), "-o", mDir.file("c.tlod")}).exitCode,
        0);
    // Down towards the rim, low enough for every level; without skirts the cracks show, so
    // every column of the report has something in it.
    std::ofstream(mDir.file("descend.json")) << R"({"fov_deg": 60, "size": [320, 240],
      "frames": 60, "keyframes": [
        {"eye": [5000, -2000, 6000], "target": [7500, 8000, 1900]},
        {"eye": [5200, 2500, 2700], "target": [7500, 8000, 1900]}]})";
  }

  RunResult bench(const std::string& report, const std::vector<std::string>& extra = {}) {
    std::vector<std::string> args = {
        "bench",  mDir.file("c.tlod"), "--flight", mDir.file("descend.json"),
        "--json", mDir.file("b.json"), "--report", report};
    args.insert(args.end(), extra.begin(), extra.end());
    return runTerralod(args);
  }

  TempDir mDir;
};

TEST_F(BenchReport, WritesFiguresPlotsAndFramesThatAgreeWithTheJson) {
  const std::string dir = mDir.file("report");
  const RunResult r =
      bench(dir, {"--source", testData("crater_lake_0513.bt"), "--tau", "0.5", "--no-skirts"});
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const auto j = nlohmann::json::parse(readWholeFile(mDir.file("b.json")));
  ASSERT_GT(j["holes_total"].get<uint64_t>(), 0u);

  // One row per frame, and the columns add up to the JSON's figures.
  const auto rows = readCsv(dir + "/frames.csv");
  ASSERT_EQ(rows.size(), 61u);
  const auto& header = rows[0];
  auto col = [&](const std::string& name) {
    return size_t(std::find(header.begin(), header.end(), name) - header.begin());
  };
  uint64_t holes = 0;
  double maxError = 0, maxFrameMs = 0, maxTriangles = 0;
  for (size_t i = 1; i < rows.size(); ++i) {
    ASSERT_EQ(rows[i].size(), header.size());
    EXPECT_EQ(std::stoul(rows[i][col("frame")]), i - 1);
    holes += std::stoull(rows[i][col("holes")]);
    if (rows[i][col("coarser")] == "0")
      maxError = std::max(maxError, std::stod(rows[i][col("error_px")]));
    maxFrameMs = std::max(maxFrameMs, std::stod(rows[i][col("frame_ms")]));
    maxTriangles = std::max(maxTriangles, std::stod(rows[i][col("triangles")]));
  }
  EXPECT_EQ(holes, j["holes_total"].get<uint64_t>());
  EXPECT_NEAR(maxError, j["max_error_px"].get<double>(), 1e-4);
  EXPECT_NEAR(maxFrameMs, j["frame_ms_max"].get<double>(), 1e-3);
  EXPECT_EQ(maxTriangles, j["triangles_max"].get<double>());

  // The plots are pictures (axes, lines, text), the contact sheet shows terrain.
  for (const char* plot : {"frame_time.png", "selection_time.png", "triangles.png",
                           "resident_mb.png", "error_px.png"}) {
    auto image = readPng(dir + "/" + plot);
    ASSERT_TRUE(image) << plot;
    EXPECT_GE(image->width, 600) << plot;
    EXPECT_GT(distinctColours(*image), 8u) << plot;
  }
  EXPECT_GT(fs::file_size(dir + "/contact_sheet.jpg"), 10'000u);

  // The report shows the figures and embeds every picture.
  const std::string md = readWholeFile(dir + "/report.md");
  for (const char* text :
       {"frame_time.png", "selection_time.png", "triangles.png", "resident_mb.png", "error_px.png",
        "contact_sheet.jpg", "most holes", "--report"})
    EXPECT_NE(md.find(text), std::string::npos) << text;
  char holesCell[64];
  std::snprintf(holesCell, sizeof holesCell, "| holes total | %llu |",
                (unsigned long long)j["holes_total"].get<uint64_t>());
  EXPECT_NE(md.find(holesCell), std::string::npos);
  // Nothing temporary is left beside it.
  for (const auto& entry : fs::directory_iterator(mDir.path()))
    EXPECT_EQ(entry.path().filename().string().find(".terralod-report"), std::string::npos);
}

TEST_F(BenchReport, WithoutASourceNoErrorPlot) {
  // Named with a trailing slash, as shells complete directories: the same directory.
  const std::string dir = mDir.file("plain");
  const RunResult r = bench(dir + "/");
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_TRUE(fs::exists(dir + "/frame_time.png"));
  EXPECT_FALSE(fs::exists(dir + "/error_px.png"));
  EXPECT_EQ(readWholeFile(dir + "/report.md").find("error_px.png"), std::string::npos);
}

TEST_F(BenchReport, AReportPathThatIsAFileIsRefusedBeforeFlying) {
  const std::string file = mDir.file("taken");
  std::ofstream(file) << "keep me";
  const RunResult r = bench(file);
  EXPECT_EQ(r.exitCode, 1);
  EXPECT_EQ(r.err, "terralod: error: " + file + ": exists and is not a directory\n");
  EXPECT_EQ(readWholeFile(file), "keep me");
  EXPECT_FALSE(fs::exists(mDir.file("b.json")));
}

}  // namespace
}  // namespace terralod::test
