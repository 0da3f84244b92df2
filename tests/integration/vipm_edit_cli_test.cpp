// `terralod edit` on VIPM tilesets: a script of brush strokes is applied to the source, the
// tileset is rebuilt and records the strokes, and `verify --source` checks it against the
// source with them applied (and fails when a recorded stroke is not what was built). Bad
// scripts are one error line that leaves the tileset as it was, and so is a killed edit.

#include <gtest/gtest.h>
#include <signal.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <random>
#include <thread>

#include "cli_expectations.h"
#include "cli_runner.h"
#include "terralod/format/terrain_edits_json.h"
#include "terralod/format/tileset_reader.h"

namespace terralod::test {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

// Strokes over the middle of a tileset: raise, smooth, lower and paint (the tileset's last
// material).
std::vector<TerrainEdit> strokesFor(const TilesetReader& t) {
  const double w = t.header().extentMax[0], h = t.header().extentMax[1];
  const uint8_t material = t.metadata().materials.back().id;
  return {{Brush::kRaise, 0.5 * w, 0.5 * h, 0.15 * w, 80.0, 0},
          {Brush::kSmooth, 0.25 * w, 0.25 * h, 0.1 * w, 1.0, 0},
          {Brush::kLower, 0.8 * w, 0.75 * h, 0.08 * w, 30.0, 0},
          {Brush::kPaint, 0.5 * w, 0.5 * h, 0.07 * w, 0.0, material}};
}

void writeScript(const std::string& path, const std::vector<TerrainEdit>& edits) {
  std::ofstream(path) << terrainEditScript(edits);
}

// `to`: `from` with the first `find` in its metadata replaced by `replace` (same length) and
// the metadata checksum made valid again.
void rewriteMetadata(const std::string& from, const std::string& to, const std::string& find,
                     const std::string& replace) {
  ASSERT_EQ(find.size(), replace.size());
  std::string bytes = readWholeFile(from);
  auto* data = reinterpret_cast<uint8_t*>(bytes.data());
  TilesetHeader header = parseHeader(std::span(data, bytes.size()), from).value();
  const size_t at = bytes.find(find, header.metadataOffset);
  ASSERT_NE(at, std::string::npos);
  ASSERT_LT(at, header.metadataOffset + header.metadataBytes);
  bytes.replace(at, find.size(), replace);
  header.metadataCrc = crc32Of(std::span(data + header.metadataOffset, header.metadataBytes));
  const std::vector<uint8_t> head = serializeHeader(header);
  std::copy(head.begin(), head.end(), data);
  std::ofstream(to, std::ios::binary) << bytes;
}

class VipmEditCli : public ::testing::Test {
 protected:
  void SetUp() override {
    fs::copy_file(testData("gzcommon_dem_squared_129.tif"), mDem);
    const RunResult built =
        runTerralod({"build", mDem, "--kind", "vipm", "--threads", "2", "-o", mTileset});
    ASSERT_EQ(built.exitCode, 0) << built.err;
  }
  RunResult verify(const std::string& tileset) {
    return runTerralod({"verify", tileset, "--source", mDem, "--threads", "2"});
  }

  TempDir mDir;
  const std::string mDem = mDir.file("dem.tif");
  const std::string mTileset = mDir.file("t.tlod");
};

TEST_F(VipmEditCli, AScriptedEditIsRecordedAndVerifiesAgainstTheEditedSource) {
  const std::string before = readWholeFile(mTileset);
  const auto strokes = strokesFor(*TilesetReader::openFile(mTileset).value());
  writeScript(mDir.file("e.json"), strokes);
  // No --source: the DEM the metadata names, next to the tileset.
  const RunResult edited = runTerralod({"edit", mTileset, "--script", mDir.file("e.json")});
  ASSERT_EQ(edited.exitCode, 0) << edited.err;
  EXPECT_TRUE(has(edited.out, "4 stroke(s) applied, 4 recorded in all")) << edited.out;
  EXPECT_NE(readWholeFile(mTileset), before);
  EXPECT_EQ(TilesetReader::openFile(mTileset).value()->metadata().edits, strokes);

  const RunResult checked = verify(mTileset);
  EXPECT_EQ(checked.exitCode, 0) << checked.out << checked.err;
  EXPECT_TRUE(has(checked.out, "verify: OK")) << checked.out;
  EXPECT_TRUE(has(checked.out, "vertex materials against the source's: 0 differ")) << checked.out;

  // A recorded stroke that is not what the chunks were built with fails verify: the raise
  // recorded as a lower (80 m the other way), and the paint left out of the materials.
  const std::string flipped = mDir.file("flipped.tlod");
  rewriteMetadata(mTileset, flipped, "\"raise\"", "\"lower\"");
  const RunResult caught = verify(flipped);
  EXPECT_EQ(caught.exitCode, 1) << caught.out;
  EXPECT_TRUE(has(caught.err, "verification failed")) << caught.err;

  // A second script adds to the record.
  writeScript(mDir.file("more.json"), {{Brush::kSmooth, 900.0, 900.0, 500.0, 0.5, 0}});
  const RunResult more =
      runTerralod({"edit", mTileset, "--script", mDir.file("more.json"), "--source", mDem});
  ASSERT_EQ(more.exitCode, 0) << more.err;
  EXPECT_TRUE(has(more.out, "1 stroke(s) applied, 5 recorded in all")) << more.out;
  EXPECT_EQ(TilesetReader::openFile(mTileset).value()->metadata().edits.size(), 5u);
}

TEST_F(VipmEditCli, BadEditsAreOneErrorLineAndLeaveTheTilesetAsItWas) {
  const std::string before = readWholeFile(mTileset);
  const std::string script = mDir.file("e.json");
  auto expectRefused = [&](const std::vector<std::string>& args, const std::string& expected) {
    SCOPED_TRACE(expected);
    const auto files = filesIn(mDir.path());
    expectOneErrorLine(runTerralod(args), expected);
    EXPECT_EQ(readWholeFile(mTileset), before);
    EXPECT_EQ(filesIn(mDir.path()), files);
  };
  const std::vector<std::string> edit = {"edit", mTileset, "--script", script};
  expectRefused(edit, script + ": cannot be read");
  std::ofstream(script) << "{\"edits\": [{\"brush\": \"dig\"}]}";
  expectRefused(edit, script + ": edits[0]: \"brush\" is not one of");
  writeScript(script, {{Brush::kRaise, -5000.0, 100.0, 300.0, 1.0, 0}});
  expectRefused(edit, script +
                          ": edits[0]: the raise brush at (-5000, 100) with radius 300 m "
                          "touches no grid point");
  writeScript(script, {{Brush::kPaint, 100.0, 100.0, 300.0, 0.0, 200}});
  expectRefused(edit, script + ": edits[0]: material 200 is not one of the tileset's (0 water");
  writeScript(script, {{Brush::kRaise, 100.0, 100.0, 300.0, 1.0, 0}});
  expectRefused({"edit", mTileset, "--script", script, "--source", testData("crater_lake_0513.bt")},
                "crater_lake_0513.bt: is 513x513 samples but");

  expectRefused({"edit", mTileset, "--script", script, "--materials", mDem},
                mTileset + ": its materials were classified from the heights");

  // A tileset whose source is nowhere to be found, and a static tileset.
  fs::create_directory(mDir.file("elsewhere"));
  const std::string moved = mDir.file("elsewhere/t.tlod");
  fs::copy_file(mTileset, moved);
  expectRefused({"edit", moved, "--script", script},
                moved + ": edit needs the source's full-resolution heights");
  const std::string fixed = mDir.file("elsewhere/static.tlod");
  ASSERT_EQ(runTerralod({"build", mDem, "--threads", "2", "-o", fixed}).exitCode, 0);
  expectRefused({"edit", fixed, "--script", script}, fixed + ": is not a VIPM tileset");
}

// Edits are written as builds are (a temporary file renamed over the tileset when complete):
// killed at any moment, an edit leaves the old tileset or the edited one, nothing else.
TEST_F(VipmEditCli, AKilledEditLeavesTheOldTilesetOrTheEditedOne) {
  const std::string dem = mDir.file("crater.bt"), tileset = mDir.file("crater.tlod");
  fs::copy_file(testData("crater_lake_0513.bt"), dem);
  ASSERT_EQ(runTerralod({"build", dem, "--kind", "vipm", "--threads", "2", "-o", tileset}).exitCode,
            0);
  const std::string old = readWholeFile(tileset);
  writeScript(mDir.file("e.json"), strokesFor(*TilesetReader::openFile(tileset).value()));
  const std::vector<std::string> args = {"edit",      tileset, "--script", mDir.file("e.json"),
                                         "--threads", "2"};
  const auto start = Clock::now();
  ASSERT_EQ(runTerralod(args).exitCode, 0);
  const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
  const std::string edited = readWholeFile(tileset);
  const unsigned seed = std::random_device()();
  SCOPED_TRACE("seed " + std::to_string(seed));
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> when(0.0, 1.2 * seconds);
  for (int kill = 0; kill < 3; ++kill) {
    std::ofstream(tileset, std::ios::binary) << old;
    const double t = kill == 0 ? 0.05 : when(random);
    SCOPED_TRACE("killed after " + std::to_string(t) + " s");
    const pid_t pid = startProgram(TERRALOD_CLI, args);
    std::this_thread::sleep_for(std::chrono::duration<double>(t));
    ::kill(pid, SIGKILL);
    int status = 0;
    waitpid(pid, &status, 0);
    const std::string now = readWholeFile(tileset);
    EXPECT_TRUE(now == old || now == edited) << "neither the old tileset nor the edited one";
    if (kill == 0) {
      EXPECT_EQ(now, old);
    }
  }
}

}  // namespace
}  // namespace terralod::test
