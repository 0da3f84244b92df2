// `terralod verify` prints each level's morph mismatch beside what it may reach, and why; a
// mismatch over that allowance fails verify.

#include <gtest/gtest.h>

#include <cmath>
#include <regex>
#include <sstream>

#include "cli_runner.h"
#include "tamper_chunk.h"
#include "terralod/format/chunk_codec.h"
#include "terralod/format/tileset_reader.h"
#include "terralod/format/tileset_writer.h"

namespace terralod::test {
namespace {

struct LevelRow {
  int level = -1;
  double step = 0, mismatch = 0, allowed = 0;
  std::string relation;  // "≤" or ">"
};

// The table rows below the roots: "level bound error samples uncovered step mismatch ≤ allowed".
std::vector<LevelRow> morphRows(const std::string& out) {
  static const std::regex row(
      R"(^\s+(\d+)\s+\S+\s+\S+\s+\d+\s+\d+\s+([0-9.]+)\s+([0-9.]+) (≤|>) ([0-9.]+)$)");
  std::vector<LevelRow> rows;
  std::istringstream in(out);
  for (std::string line; std::getline(in, line);) {
    std::smatch m;
    if (std::regex_match(line, m, row))
      rows.push_back({std::stoi(m[1]), std::stod(m[2]), std::stod(m[3]), std::stod(m[5]), m[4]});
  }
  return rows;
}

TEST(VerifyTolerance, PrintsEachLevelsAllowanceAndWhyItHolds) {
  TempDir dir;
  const std::string dem = testData("gzcommon_dem_squared_129.tif");
  const std::string good = dir.file("good.tlod");
  ASSERT_EQ(runTerralod({"build", dem, "--no-texture", "--chunk-cells", "32", "-o", good}).exitCode,
            0);
  const RunResult r = runTerralod({"verify", good, "--source", dem});
  ASSERT_EQ(r.exitCode, 0) << r.out << r.err;
  const std::vector<LevelRow> rows = morphRows(r.out);
  auto reader = TilesetReader::openFile(good).value();
  const uint32_t levels = reader->header().levelCount;
  ASSERT_GE(levels, 3u);
  ASSERT_EQ(rows.size(), levels - 1) << r.out;
  for (const LevelRow& row : rows) {
    SCOPED_TRACE(row.level);
    EXPECT_EQ(row.relation, "≤");
    EXPECT_LE(row.mismatch, row.allowed);
    // The allowance is half this level's step plus half its parent's, plus 1e-6 m.
    const LevelRow* parent = nullptr;
    for (const LevelRow& p : rows)
      if (p.level == row.level - 1) parent = &p;
    if (parent) {
      EXPECT_NEAR(row.allowed, 0.5 * (row.step + parent->step) + 1e-6, 2e-6);
    }
  }
  EXPECT_NE(r.out.find("morph mismatch allowed = (height step + parent level's step) / 2 + 1e-6 m"),
            std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("verify: OK"), std::string::npos);

  // One vertex of a level-1 chunk morphing to just over twice the allowance off its parent.
  uint32_t victim = 0;
  while (reader->nodes()[victim].level != 1) ++victim;
  const double allowed = rows.front().allowed;
  const std::string bad = dir.file("bad.tlod");
  tamperChunk(good, bad, victim, [&](ChunkGeometry& g) {
    ChunkPart& part = g.parts[0];
    ChunkVertex& v = part.vertices[part.indices[part.surfaceIndexCount / 2]];
    v.morphDelta = int16_t(v.morphDelta + int(std::ceil(2.0 * allowed / g.zStep)) + 1);
  });
  const RunResult failed = runTerralod({"verify", bad, "--source", dem});
  EXPECT_EQ(failed.exitCode, 1) << failed.out;
  const std::vector<LevelRow> badRows = morphRows(failed.out);
  ASSERT_FALSE(badRows.empty()) << failed.out;
  EXPECT_EQ(badRows.front().level, 1);
  EXPECT_EQ(badRows.front().relation, ">");
  EXPECT_GT(badRows.front().mismatch, badRows.front().allowed);
  EXPECT_NE(failed.err.find("fully morphed surface is"), std::string::npos) << failed.err;
  EXPECT_NE(failed.err.find("verification failed"), std::string::npos) << failed.err;
}

}  // namespace
}  // namespace terralod::test
