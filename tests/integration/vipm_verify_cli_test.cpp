// `terralod verify` on VIPM tilesets: a tileset `build --kind vipm` wrote passes every check
// (each LOD's true error, the material rules, parts, fallback roots, flanges); the rules are
// failures only when the tileset promises them; a source that is not the one it was built
// from fails.

#include <gdal_priv.h>
#include <gtest/gtest.h>

#include "cli_expectations.h"
#include "cli_runner.h"

namespace terralod::test {
namespace {

const std::string kDem = testData("gzcommon_dem_squared_129.tif");

bool has(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

class VipmVerifyCli : public ::testing::Test {
 protected:
  TempDir mDir;
};

TEST_F(VipmVerifyCli, ABuiltTilesetPassesEveryCheck) {
  const std::string out = mDir.file("v.tlod");
  ASSERT_EQ(runTerralod({"build", kDem, "--kind", "vipm", "--threads", "2", "-o", out}).exitCode,
            0);
  const RunResult verified = runTerralod({"verify", out, "--source", kDem, "--threads", "2"});
  EXPECT_EQ(verified.exitCode, 0) << verified.out << verified.err;
  EXPECT_TRUE(has(verified.out, "verify: OK")) << verified.out;
  EXPECT_TRUE(has(verified.out, ", 0 break a material rule (built with the rules)"))
      << verified.out;
  EXPECT_TRUE(has(verified.out, "vertex materials against the source's: 0 differ")) << verified.out;
  EXPECT_TRUE(has(verified.out, "largest difference 0.000000 m")) << verified.out;
}

TEST_F(VipmVerifyCli, RuleBreaksFailOnlyATilesetBuiltWithTheRules) {
  const std::string out = mDir.file("norules.tlod");
  ASSERT_EQ(
      runTerralod({"build", kDem, "--kind", "vipm", "--no-material-rules", "-o", out}).exitCode, 0);
  const RunResult verified = runTerralod({"verify", out, "--source", kDem});
  EXPECT_EQ(verified.exitCode, 0) << verified.err;
  EXPECT_TRUE(has(verified.out, "(built with --no-material-rules)")) << verified.out;
  EXPECT_FALSE(has(verified.out, ", 0 break a material rule")) << verified.out;
}

TEST_F(VipmVerifyCli, FailsAgainstASourceItWasNotBuiltFrom) {
  const std::string out = mDir.file("v.tlod");
  ASSERT_EQ(runTerralod({"build", kDem, "--kind", "vipm", "-o", out}).exitCode, 0);
  // The same DEM with a 3 m bump in one corner.
  const std::string bumped = mDir.file("bumped.tif");
  GDALAllRegister();
  {
    GDALDatasetUniquePtr dem(GDALDataset::Open(kDem.c_str(), GDAL_OF_RASTER));
    ASSERT_TRUE(dem);
    GDALDriver* gtiff = GetGDALDriverManager()->GetDriverByName("GTiff");
    GDALDatasetUniquePtr copy(
        gtiff->CreateCopy(bumped.c_str(), dem.get(), false, nullptr, nullptr, nullptr));
    ASSERT_TRUE(copy);
    std::vector<double> window(100);
    GDALRasterBand* band = copy->GetRasterBand(1);
    ASSERT_EQ(band->RasterIO(GF_Read, 0, 0, 10, 10, window.data(), 10, 10, GDT_Float64, 0, 0),
              CE_None);
    for (double& v : window) v += 3.0;
    ASSERT_EQ(band->RasterIO(GF_Write, 0, 0, 10, 10, window.data(), 10, 10, GDT_Float64, 0, 0),
              CE_None);
  }
  const RunResult verified = runTerralod({"verify", out, "--source", bumped});
  EXPECT_EQ(verified.exitCode, 1);
  EXPECT_TRUE(has(verified.err, ": true error ")) << verified.err;
  EXPECT_TRUE(has(verified.err, "verification failed")) << verified.err;
}

}  // namespace
}  // namespace terralod::test
