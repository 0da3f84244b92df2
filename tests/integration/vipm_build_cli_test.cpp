// `terralod build --kind vipm` from the command line: it writes a VIPM tileset that `info`
// describes (kind, materials), and refuses bad materials and options that make no sense with
// one line each, a non-zero exit and nothing written.

#include <gdal_priv.h>
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "cli_expectations.h"
#include "cli_runner.h"

namespace terralod::test {
namespace {

const std::string kDem = testData("gzcommon_dem_squared_129.tif");

// A Byte (or Float32) raster on the DEM's grid, shifted by `shiftX` of its widths, holding
// value(x, y).
template <typename Value>
void writeClasses(const std::string& path, GDALDataType type, double shiftX, Value value) {
  GDALAllRegister();
  GDALDatasetUniquePtr dem(GDALDataset::Open(kDem.c_str(), GDAL_OF_RASTER));
  ASSERT_TRUE(dem);
  const int w = dem->GetRasterXSize(), h = dem->GetRasterYSize();
  GDALDriver* gtiff = GetGDALDriverManager()->GetDriverByName("GTiff");
  GDALDatasetUniquePtr out(gtiff->Create(path.c_str(), w, h, 1, type, nullptr));
  double gt[6];
  dem->GetGeoTransform(gt);
  gt[0] += shiftX * w * gt[1];
  out->SetGeoTransform(gt);
  out->SetProjection(dem->GetProjectionRef());
  std::vector<double> row(size_t(w), 0.0);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) row[size_t(x)] = double(value(x, y));
    ASSERT_EQ(
        out->GetRasterBand(1)->RasterIO(GF_Write, 0, y, w, 1, row.data(), w, 1, GDT_Float64, 0, 0),
        CE_None);
  }
}

class VipmBuildCli : public ::testing::Test {
 protected:
  void SetUp() override {
    writeClasses(mDir.file("classes.tif"), GDT_Byte, 0.0, [](int x, int) { return 3 + x / 50; });
    writeClasses(mDir.file("far.tif"), GDT_Byte, 10.0, [](int x, int) { return x / 50; });
    writeClasses(mDir.file("many.tif"), GDT_Byte, 0.0, [](int x, int) { return x / 12; });
    writeClasses(mDir.file("heights.tif"), GDT_Float32, 0.0,
                 [](int x, int y) { return 100.0 + 0.37 * x + 0.11 * y; });
  }
  TempDir mDir;
};

TEST_F(VipmBuildCli, WritesAVipmTilesetThatInfoDescribes) {
  const std::string out = mDir.file("v.tlod");
  const RunResult built = runTerralod({"build", kDem, "--kind", "vipm", "--materials",
                                       mDir.file("classes.tif"), "--threads", "2", "-o", out});
  ASSERT_EQ(built.exitCode, 0) << built.err;
  EXPECT_NE(built.out.find("ms CPU per leaf chunk"), std::string::npos) << built.out;
  const RunResult info = runTerralod({"info", out, "--json"});
  ASSERT_EQ(info.exitCode, 0) << info.err;
  const auto j = nlohmann::json::parse(info.out);
  EXPECT_EQ(j["kind"], "vipm");
  ASSERT_EQ(j["materials"].size(), 3u);  // values 3, 4, 5 over the DEM
  EXPECT_EQ(j["materials"][0]["id"], 3);
  EXPECT_EQ(j["materials"][0]["name"], "class 3");
  EXPECT_EQ(j["materials"][0]["color"].get<std::string>().size(), 7u);
  EXPECT_EQ(j["metadata"]["build"]["materials"], "classes.tif");
  EXPECT_EQ(j["metadata"]["build"]["material_rules"], true);
  // Blot roots by default: leaves stop at 4 × --max-error (1 m), roots take over at twice
  // their largest last error.
  EXPECT_EQ(j["metadata"]["build"]["blot_error"], 4.0);
  EXPECT_LE(j["level_error"][0].get<double>(), 8.0 + 1e-4);
  const RunResult text = runTerralod({"info", out});
  EXPECT_NE(text.out.find("kind            vipm"), std::string::npos) << text.out;
  EXPECT_NE(text.out.find("0: class 3 (id 3, #"), std::string::npos) << text.out;
  // Normal maps only: version 2, textured, 129/65 texels a side.
  EXPECT_EQ(j["format_version"], 2);
  EXPECT_EQ(j["textured"], true);
  EXPECT_EQ(j["texture_bytes"], j["metadata"]["texture"]["bytes"]);
  EXPECT_NE(text.out.find("textures        normal maps only (BC5"), std::string::npos) << text.out;

  // --blot-error off: leaves simplify as far as the rules allow, roots take over beyond.
  const RunResult off = runTerralod({"build", kDem, "--kind", "vipm", "--blot-error", "off",
                                     "--threads", "2", "-o", mDir.file("off.tlod")});
  ASSERT_EQ(off.exitCode, 0) << off.err;
  const auto o = nlohmann::json::parse(runTerralod({"info", mDir.file("off.tlod"), "--json"}).out);
  EXPECT_TRUE(o["metadata"]["build"]["blot_error"].is_null());
  EXPECT_GT(o["level_error"][0].get<double>(), 8.0);

  const RunResult statik = runTerralod({"build", kDem, "--no-texture", "-o", mDir.file("s.tlod")});
  ASSERT_EQ(statik.exitCode, 0) << statik.err;
  const auto s = nlohmann::json::parse(runTerralod({"info", mDir.file("s.tlod"), "--json"}).out);
  EXPECT_EQ(s["kind"], "static");
  EXPECT_TRUE(s["materials"].empty());
}

TEST_F(VipmBuildCli, RefusesBadMaterialsAndOptionsThatDoNotApply) {
  const std::string d = mDir.path().string(), out = d + "/out.tlod";
  struct Case {
    std::string name;
    std::vector<std::string> args;
    std::string expected;
  };
  const std::vector<Case> cases = {
      {"materials not overlapping",
       {"build", kDem, "--kind", "vipm", "--materials", d + "/far.tif", "-o", out},
       "far.tif: does not overlap the DEM"},
      {"more than 8 classes",
       {"build", kDem, "--kind", "vipm", "--materials", d + "/many.tif", "-o", out},
       "many.tif: has 11 classes over the DEM; at most 8"},
      {"continuous raster",
       {"build", kDem, "--kind", "vipm", "--materials", d + "/heights.tif", "-o", out},
       "heights.tif: has non-integer values"},
      {"missing materials",
       {"build", kDem, "--kind", "vipm", "--materials", d + "/nope.tif", "-o", out},
       "nope.tif: no such file"},
      {"materials with static",
       {"build", kDem, "--materials", d + "/classes.tif", "-o", out},
       "--materials applies to --kind vipm only"},
      {"no rules with static",
       {"build", kDem, "--no-material-rules", "-o", out},
       "--no-material-rules applies to --kind vipm only"},
      {"blot error with static",
       {"build", kDem, "--blot-error", "4", "-o", out},
       "--blot-error applies to --kind vipm only"},
      {"blot error neither metres nor off",
       {"build", kDem, "--kind", "vipm", "--blot-error", "far", "-o", out},
       "--blot-error: must be a number greater than 0 or off (got far)"},
      {"blot error below max error",
       {"build", kDem, "--kind", "vipm", "--max-error", "2", "--blot-error", "1", "-o", out},
       "--blot-error must be at least --max-error"},
      {"palette without materials",
       {"build", kDem, "--kind", "vipm", "--palette", d + "/p.json", "-o", out},
       "--palette names the classes of --materials, which is missing"},
      {"texture with vipm",
       {"build", kDem, "--kind", "vipm", "--texture", d + "/classes.tif", "-o", out},
       "--texture does not apply to --kind vipm"},
      {"min tau with vipm",
       {"build", kDem, "--kind", "vipm", "--min-tau", "1", "-o", out},
       "--min-tau does not apply to --kind vipm"},
      {"no texture with vipm",
       {"build", kDem, "--kind", "vipm", "--no-texture", "-o", out},
       "--no-texture does not apply to --kind vipm (its chunks are lit by their stored normal "
       "maps)"},
      {"greedy meshes with vipm",
       {"build", kDem, "--kind", "vipm", "--mesher", "greedy", "-o", out},
       "--mesher applies to --kind static only"},
      {"chunk cells with vipm",
       {"build", kDem, "--kind", "vipm", "--chunk-cells", "32", "-o", out},
       "--chunk-cells: VIPM chunks are always 64 cells"},
      {"error too fine",
       {"build", kDem, "--kind", "vipm", "--max-error", "0.00001", "-o", out},
       "gzcommon_dem_squared_129.tif: --max-error 1e-05 m is too fine for 16-bit heights"},
      {"unknown kind", {"build", kDem, "--kind", "rtin", "-o", out}, "--kind"},
  };
  const std::vector<std::string> before = filesIn(mDir.path());
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    expectOneErrorLine(runTerralod(c.args), c.expected);
    EXPECT_EQ(filesIn(mDir.path()), before) << "partial output left behind";
  }
}

}  // namespace
}  // namespace terralod::test
