// Inputs that are not heights: photos, RGB-encoded tiles read without their encoding, greyscale
// pictures, and numeric options out of range. Each is refused (or warned about) in one plain
// line that says what to do instead, and nothing is left behind.

#include <gdal_priv.h>
#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <vector>

#include "cli_expectations.h"
#include "cli_runner.h"
#include "terralod/format/tileset_reader.h"

namespace terralod::test {
namespace {

namespace fs = std::filesystem;

// Writes `bands` (each columns x rows bytes) through GDAL's `driver` (JPEG, PNG), with no
// georeferencing: a picture as a camera or an image editor leaves it.
void writePicture(const std::string& path, const char* driver, int columns, int rows,
                  const std::vector<std::vector<uint8_t>>& bands) {
  GDALAllRegister();
  GDALDatasetUniquePtr mem(GetGDALDriverManager()->GetDriverByName("MEM")->Create(
      "", columns, rows, int(bands.size()), GDT_Byte, nullptr));
  for (size_t b = 0; b < bands.size(); ++b)
    ASSERT_EQ(mem->GetRasterBand(int(b) + 1)
                  ->RasterIO(GF_Write, 0, 0, columns, rows, const_cast<uint8_t*>(bands[b].data()),
                             columns, rows, GDT_Byte, 0, 0),
              CE_None);
  GDALDatasetUniquePtr(GetGDALDriverManager()->GetDriverByName(driver)->CreateCopy(
      path.c_str(), mem.get(), FALSE, nullptr, nullptr, nullptr));
  ASSERT_TRUE(fs::exists(path)) << path;
}

// A smooth picture: band b is a different slanted ramp with a bump, 0..255.
std::vector<std::vector<uint8_t>> pictureBands(int columns, int rows, int count) {
  std::vector<std::vector<uint8_t>> bands(size_t(count),
                                          std::vector<uint8_t>(size_t(columns) * rows));
  for (int b = 0; b < count; ++b)
    for (int y = 0; y < rows; ++y)
      for (int x = 0; x < columns; ++x) {
        const double u = double(x) / (columns - 1), v = double(y) / (rows - 1);
        const double bump = std::exp(-((u - 0.5) * (u - 0.5) + (v - 0.4) * (v - 0.4)) * 12.0);
        const double value = 40.0 * b + 60.0 * (u + (b + 1) * 0.5 * v) / (1 + b) + 90.0 * bump;
        bands[size_t(b)][size_t(y) * columns + x] = uint8_t(std::clamp(value, 0.0, 255.0));
      }
  return bands;
}

class NonHeightInputs : public ::testing::Test {
 protected:
  std::string at(const std::string& name) const { return mDir.file(name); }
  nlohmann::json infoJson(const std::string& tileset) {
    const RunResult r = runTerralod({"info", tileset, "--json"});
    EXPECT_EQ(r.exitCode, 0) << r.err;
    return nlohmann::json::parse(r.out, nullptr, false);
  }
  nlohmann::json sourceMetadata(const std::string& tileset) {
    auto reader = TilesetReader::openFile(tileset);
    EXPECT_TRUE(reader.ok());
    return nlohmann::json::parse((*reader)->metadataJson())["source"];
  }
  TempDir mDir;
};

constexpr const char* kHint =
    "bands of 8-bit values, like a picture, not heights: give --encoding terrain-rgb|terrarium "
    "for RGB-encoded heights, or --band N to take one band as heights";

// A JPEG photo (three 8-bit bands) used to build a 0..255 m relief from its red channel.
TEST_F(NonHeightInputs, APhotoIsRefusedUnlessABandIsChosen) {
  writePicture(at("photo.jpg"), "JPEG", 120, 90, pictureBands(120, 90, 3));
  const std::vector<std::string> before = filesIn(mDir.path());
  const RunResult refused = runTerralod({"build", at("photo.jpg"), "-o", at("photo.tlod")});
  expectOneErrorLine(refused, at("photo.jpg") + ": has 3 " + kHint);
  EXPECT_EQ(filesIn(mDir.path()), before) << "output left behind";

  // The RGB Landsat image bundled for draping is refused the same way.
  expectOneErrorLine(
      runTerralod({"build", testData("zion_landsat8_rgb_utm12_30m.tif"), "-o", at("l.tlod")}),
      "zion_landsat8_rgb_utm12_30m.tif: has 3 " + std::string(kHint));
  EXPECT_EQ(filesIn(mDir.path()), before) << "output left behind";

  // --band N takes that band as heights, says so in the metadata, and verify reads the same
  // band (band 2 differs from band 1 by tens of metres: reading band 1 would fail the bound).
  for (int band : {1, 2}) {
    SCOPED_TRACE(band);
    const std::string tileset = at("photo" + std::to_string(band) + ".tlod");
    const RunResult built =
        runTerralod({"build", at("photo.jpg"), "--band", std::to_string(band), "-o", tileset});
    ASSERT_EQ(built.exitCode, 0) << built.err;
    EXPECT_EQ(sourceMetadata(tileset).value("band", 0), band);
    const RunResult verified = runTerralod({"verify", tileset, "--source", at("photo.jpg")});
    EXPECT_EQ(verified.exitCode, 0) << verified.out << verified.err;
    const auto extent = infoJson(tileset)["extent"];
    EXPECT_GE(extent["min"][2].get<double>(), -1.0);
    EXPECT_LE(extent["max"][2].get<double>(), 256.0);
  }

  // A band that is not there, and a band with an encoding.
  expectOneErrorLine(runTerralod({"build", at("photo.jpg"), "--band", "4", "-o", at("photo.tlod")}),
                     at("photo.jpg") + ": has 3 band(s); --band must be 1 to 3 (got 4)");
  expectOneErrorLine(runTerralod({"build", at("photo.jpg"), "--band", "0", "-o", at("photo.tlod")}),
                     "--band: must be a whole number, 1 or more (got 0)");
  expectOneErrorLine(runTerralod({"build", testData("loadersgl_terrarium_256.png"), "--band", "1",
                                  "--encoding", "terrarium", "-o", at("photo.tlod")}),
                     "--band and --encoding contradict each other");
  EXPECT_FALSE(fs::exists(at("photo.tlod")));
}

// A Mapbox terrain-RGB tile read plainly used to give a flat slab of its high byte (1..2 m).
TEST_F(NonHeightInputs, AnRgbEncodedTileWithoutItsEncodingIsRefusedWithAHint) {
  const int w = 64, h = 48;
  std::vector<std::vector<uint8_t>> rgb(3, std::vector<uint8_t>(size_t(w) * h));
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const double metres = 1200.0 + 8.0 * x + 5.0 * y + 30.0 * std::sin(x * 0.2);
      const uint32_t code = uint32_t(std::lround((metres + 10000.0) * 10.0));
      for (int b = 0; b < 3; ++b) rgb[size_t(b)][size_t(y) * w + x] = uint8_t(code >> (16 - 8 * b));
    }
  writePicture(at("mapbox.png"), "PNG", w, h, rgb);
  const std::vector<std::string> before = filesIn(mDir.path());
  expectOneErrorLine(runTerralod({"build", at("mapbox.png"), "-o", at("m.tlod")}),
                     at("mapbox.png") + ": has 3 " + kHint);
  // The bundled Terrarium tile too.
  expectOneErrorLine(
      runTerralod({"build", testData("loadersgl_terrarium_256.png"), "-o", at("m.tlod")}),
      "loadersgl_terrarium_256.png: has 3 " + std::string(kHint));
  EXPECT_EQ(filesIn(mDir.path()), before) << "output left behind";

  // With its encoding it builds the relief it holds, and no band is recorded.
  const RunResult built =
      runTerralod({"build", at("mapbox.png"), "--encoding", "terrain-rgb", "-o", at("m.tlod")});
  ASSERT_EQ(built.exitCode, 0) << built.err;
  const auto extent = infoJson(at("m.tlod"))["extent"];
  EXPECT_NEAR(extent["min"][2].get<double>(), 1200.0, 31.0);
  EXPECT_GT(extent["max"][2].get<double>(), 1700.0);
  EXPECT_FALSE(sourceMetadata(at("m.tlod")).contains("band"));
}

// One 8-bit band without georeferencing: built (it may be a game heightmap), with one warning
// saying it looks like an image instead of the usual "1 m assumed" one.
TEST_F(NonHeightInputs, AGreyPictureWithoutGeoreferencingIsWarnedAbout) {
  writePicture(at("grey.png"), "PNG", 100, 80, pictureBands(100, 80, 1));
  const RunResult built = runTerralod({"build", at("grey.png"), "-o", at("g.tlod")});
  ASSERT_EQ(built.exitCode, 0) << built.err;
  const auto lines = built.errLines();
  ASSERT_EQ(lines.size(), 1u) << built.err;
  EXPECT_EQ(lines[0], "terralod: warning: " + at("grey.png") +
                          ": looks like an image, not heights (one 8-bit band, no "
                          "georeferencing): its values 0..255 are taken as metres on 1 m cells; "
                          "for a heightmap give --spacing and --vertical-scale");
  // Single-band sources record no band: their tilesets keep their bytes.
  EXPECT_FALSE(sourceMetadata(at("g.tlod")).contains("band"));

  // Given a spacing, it is taken as the heightmap it was said to be: no warning.
  const RunResult spaced =
      runTerralod({"build", at("grey.png"), "--spacing", "30", "-o", at("g30.tlod")});
  ASSERT_EQ(spaced.exitCode, 0) << spaced.err;
  EXPECT_TRUE(spaced.errLines().empty()) << spaced.err;

  // A 16-bit heightmap without georeferencing only gets the spacing warning.
  GDALAllRegister();
  {
    GDALDatasetUniquePtr mem(
        GetGDALDriverManager()->GetDriverByName("MEM")->Create("", 40, 30, 1, GDT_UInt16, nullptr));
    std::vector<uint16_t> v(40 * 30);
    for (size_t i = 0; i < v.size(); ++i) v[i] = uint16_t(1000 + (i % 40) * 7 + (i / 40) * 3);
    ASSERT_EQ(
        mem->GetRasterBand(1)->RasterIO(GF_Write, 0, 0, 40, 30, v.data(), 40, 30, GDT_UInt16, 0, 0),
        CE_None);
    GDALDatasetUniquePtr(GetGDALDriverManager()->GetDriverByName("PNG")->CreateCopy(
        at("h16.png").c_str(), mem.get(), FALSE, nullptr, nullptr, nullptr));
  }
  const RunResult heights = runTerralod({"build", at("h16.png"), "-o", at("h16.tlod")});
  ASSERT_EQ(heights.exitCode, 0) << heights.err;
  ASSERT_EQ(heights.errLines().size(), 1u) << heights.err;
  EXPECT_NE(heights.err.find("no georeferencing: 1 m assumed"), std::string::npos) << heights.err;
}

// Numeric options out of range: one plain line each, "--option: must be ... (got X)", where
// CLI11 printed "Value 0 not in range 0.000000 to 1797...(300 digits)".
TEST_F(NonHeightInputs, NumericOptionsOutOfRangeGetOnePlainLine) {
  const std::string dem = testData("gzcommon_dem_squared_129.tif");
  const std::string tileset = testData("golden/v2/gully.tlod");
  const std::string out = at("out.tlod");
  const std::vector<std::string> before = filesIn(mDir.path());
  {
    const RunResult r = runTerralod({"build", dem, "--max-error", "0", "-o", out});
    EXPECT_EQ(r.exitCode, 1);
    ASSERT_EQ(r.errLines().size(), 1u) << r.err;
    EXPECT_EQ(r.errLines()[0],
              "terralod: error: --max-error: must be greater than 0 (got 0) (see --help)");
    EXPECT_TRUE(r.out.empty()) << r.out;
  }
  struct Case {
    std::vector<std::string> args;
    std::string line;  ///< after "terralod: error: ", before " (see --help)"
  };
  const std::vector<Case> cases = {
      {{"build", dem, "--max-error", "-1", "-o", out},
       "--max-error: must be greater than 0 (got -1)"},
      {{"build", dem, "--max-error", "abc", "-o", out},
       "--max-error: must be a number greater than 0 (got abc)"},
      {{"build", dem, "--max-error", "inf", "-o", out},
       "--max-error: must be a number greater than 0 (got inf)"},
      {{"build", dem, "--spacing", "30,0", "-o", out}, "--spacing: must be greater than 0 (got 0)"},
      {{"build", dem, "--vertical-scale", "0", "-o", out},
       "--vertical-scale: must be greater than 0 (got 0)"},
      {{"build", dem, "--min-tau", "-2", "-o", out}, "--min-tau: must be greater than 0 (got -2)"},
      {{"build", dem, "--memory-mb", "0", "-o", out},
       "--memory-mb: must be a whole number, 1 or more (got 0)"},
      {{"build", dem, "--zstd-level", "30", "-o", out},
       "--zstd-level: must be a whole number from 1 to 22 (got 30)"},
      {{"build", dem, "--threads", "-1", "-o", out},
       "--threads: must be a whole number, 0 or more (got -1)"},
      {{"build", dem, "--chunk-cells", "1.5", "-o", out},
       "--chunk-cells: must be a whole number, 0 or more (got 1.5)"},
      {{"synth", "--size", "x", "-o", at("s.tif")}, "--size: must be a whole number (got x)"},
      {{"synth", "--size", "65", "--spacing", "0", "-o", at("s.tif")},
       "--spacing: must be greater than 0 (got 0)"},
      {{"synth", "--size", "65", "--seed", "-3", "-o", at("s.tif")},
       "--seed: must be a whole number, 0 or more (got -3)"},
      {{"verify", tileset, "--source", dem, "--threads", "two"},
       "--threads: must be a whole number, 0 or more (got two)"},
      {{"export", tileset, "--level", "one", "-o", at("m.obj")},
       "--level: must be a whole number (got one)"},
      {{"render", tileset, "--tau", "0", "-o", at("r.png")},
       "--tau: must be greater than 0 (got 0)"},
      {{"render", tileset, "--fov", "180", "-o", at("r.png")},
       "--fov: must be from 1 to 179 (got 180)"},
      {{"render", tileset, "--cache-mb", "0", "-o", at("r.png")},
       "--cache-mb: must be greater than 0 (got 0)"},
      {{"render", tileset, "--haze", "-0.5", "-o", at("r.png")},
       "--haze: must be 0 or more (got -0.5)"},
      {{"bench", tileset, "--auto-flight", "--haze", "thick", "--json", at("b.json")},
       "--haze: must be a number, 0 or more (got thick)"},
      {{"render", tileset, "--sun", "315,high", "-o", at("r.png")},
       "--sun: must be a finite number (got high)"},
      {{"render", tileset, "--auto-flight", "--frames", "0", "--frames-dir", at("f")},
       "--frames: must be a whole number, 1 or more (got 0)"},
      {{"render", tileset, "--auto-flight", "--every", "0", "--frames-dir", at("f")},
       "--every: must be a whole number, 1 or more (got 0)"},
      {{"bench", tileset, "--auto-flight", "--metric-stride", "0", "--json", at("b.json")},
       "--metric-stride: must be a whole number, 1 or more (got 0)"},
      {{"view", tileset, "--tau", "0"}, "--tau: must be greater than 0 (got 0)"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.line);
    const RunResult r = runTerralod(c.args);
    EXPECT_EQ(r.exitCode, 1);
    ASSERT_EQ(r.errLines().size(), 1u) << r.err;
    EXPECT_EQ(r.errLines()[0], "terralod: error: " + c.line + " (see --help)");
    EXPECT_EQ(filesIn(mDir.path()), before) << "output left behind";
  }
}

}  // namespace
}  // namespace terralod::test
