// `terralod synth` feeds `build`: its GeoTIFF carries the spacing, builds and verifies, and the
// same arguments give the same file.

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "cli_runner.h"

namespace terralod::test {
namespace {

TEST(Synth, WritesADemThatBuildsAndVerifies) {
  TempDir dir;
  const std::string dem = dir.file("synth.tif"), tileset = dir.file("synth.tlod");
  const RunResult synth =
      runTerralod({"synth", "--size", "700", "--seed", "9", "--spacing", "5", "-o", dem});
  ASSERT_EQ(synth.exitCode, 0) << synth.err;
  EXPECT_NE(synth.out.find("700x700 samples at 5 m, seed 9"), std::string::npos) << synth.out;
  EXPECT_TRUE(synth.err.empty()) << "progress must stay quiet when stderr is not a terminal";

  const RunResult built = runTerralod({"build", dem, "-o", tileset, "--max-error", "0.5"});
  ASSERT_EQ(built.exitCode, 0) << built.err;
  const RunResult info = runTerralod({"info", tileset, "--json"});
  ASSERT_EQ(info.exitCode, 0) << info.err;
  const auto j = nlohmann::json::parse(info.out);
  EXPECT_EQ(j["spacing"], nlohmann::json({5.0, 5.0}));
  EXPECT_EQ(j["source_size"], nlohmann::json({700, 700}));
  EXPECT_EQ(j["extent"]["max"][0], 3495.0);
  const RunResult verified = runTerralod({"verify", tileset, "--source", dem});
  EXPECT_EQ(verified.exitCode, 0) << verified.out << verified.err;
}

TEST(Synth, IsDeterministic) {
  TempDir dir;
  for (const char* name : {"a.tif", "b.tif"})
    ASSERT_EQ(runTerralod({"synth", "--size", "300", "--seed", "4", "-o", dir.file(name)}).exitCode,
              0);
  EXPECT_EQ(readWholeFile(dir.file("a.tif")), readWholeFile(dir.file("b.tif")));
  ASSERT_EQ(
      runTerralod({"synth", "--size", "300", "--seed", "5", "-o", dir.file("c.tif")}).exitCode, 0);
  EXPECT_NE(readWholeFile(dir.file("a.tif")), readWholeFile(dir.file("c.tif")));
}

}  // namespace
}  // namespace terralod::test
