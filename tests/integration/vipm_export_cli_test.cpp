// `terralod export --error E` on a VIPM tileset writes every leaf at the level drawn for E:
// fewer triangles for a larger error; --level on a VIPM tileset and --error on a static one
// are refused with nothing written.

#include <gtest/gtest.h>

#include <filesystem>
#include <regex>

#include "cli_runner.h"
#include "shared_directory.h"

namespace terralod::test {
namespace {

uint64_t trianglesWritten(const std::string& out) {
  std::smatch m;
  if (!std::regex_search(out, m, std::regex("([0-9]+) triangles"))) return 0;
  return std::stoull(m[1]);
}

TEST(VipmExportCli, WritesTheSurfaceDrawnForAnError) {
  TempDir dir;
  SharedDirectory tileset =
      sharedDirectory("crater-vipm", programStamp(TERRALOD_CLI), [](const std::string& d) {
        const RunResult built = runTerralod(
            {"build", testData("crater_lake_0513.bt"), "--kind", "vipm", "-o", d + "/c.tlod"});
        return built.exitCode == 0 ? std::string() : built.err;
      });
  ASSERT_EQ(tileset.error, "");
  uint64_t previous = UINT64_MAX;
  for (const char* error : {"0", "2", "8"}) {
    const RunResult r =
        runTerralod({"export", tileset.file("c.tlod"), "--error", error, "-o", dir.file("e.obj")});
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const uint64_t triangles = trianglesWritten(r.out);
    EXPECT_GT(triangles, 1000u) << r.out;
    EXPECT_LT(triangles, previous) << "--error " << error;
    previous = triangles;
  }
  std::filesystem::remove(dir.file("e.obj"));
  const RunResult level =
      runTerralod({"export", tileset.file("c.tlod"), "--level", "1", "-o", dir.file("e.obj")});
  EXPECT_NE(level.exitCode, 0);
  EXPECT_NE(level.err.find("use --error"), std::string::npos) << level.err;
  const RunResult negative =
      runTerralod({"export", tileset.file("c.tlod"), "--error", "-1", "-o", dir.file("e.obj")});
  EXPECT_NE(negative.exitCode, 0);
  EXPECT_FALSE(std::filesystem::exists(dir.file("e.obj")));
}

}  // namespace
}  // namespace terralod::test
