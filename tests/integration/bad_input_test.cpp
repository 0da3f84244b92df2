// The bad-input matrix of `terralod build`, `info` and `verify`: every broken input gets exactly
// one error line naming the file and the problem, a non-zero exit, and no output.

#include <gdal_priv.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "cli_expectations.h"
#include "cli_runner.h"

namespace terralod::test {
namespace {

namespace fs = std::filesystem;

struct BadCase {
  std::string name;
  std::vector<std::string> args;  ///< "{dir}" is replaced by the scratch directory
  std::string expected;           ///< substring of the one error line
};

class BadInputs : public ::testing::Test {
 protected:
  void SetUp() override {
    GDALAllRegister();
    GDALDriver* gtiff = GetGDALDriverManager()->GetDriverByName("GTiff");
    GDALDatasetUniquePtr(
        gtiff->Create(mDir.file("one.tif").c_str(), 1, 1, 1, GDT_Float32, nullptr));
    {
      GDALDatasetUniquePtr ds(
          gtiff->Create(mDir.file("allvoid.tif").c_str(), 20, 10, 1, GDT_Int16, nullptr));
      ds->GetRasterBand(1)->SetNoDataValue(-32768);
      (void)ds->GetRasterBand(1)->Fill(-32768);
    }
    std::ofstream(mDir.file("empty.tif")).close();
    std::ofstream(mDir.file("notes.txt")) << "not a raster\n";
    fs::copy_file(testData("zion_srtm3_utm12_30m.tif"), mDir.file("truncated.tif"));
    fs::resize_file(mDir.file("truncated.tif"), fs::file_size(mDir.file("truncated.tif")) / 2);
    // A valid tileset, then damaged copies of it.
    const RunResult built = runTerralod(
        {"build", testData("gzcommon_dem_squared_129.tif"), "-o", mDir.file("good.tlod")});
    ASSERT_EQ(built.exitCode, 0) << built.err;
    const std::string good = readWholeFile(mDir.file("good.tlod"));
    std::ofstream(mDir.file("truncated.tlod"), std::ios::binary)
        << good.substr(0, good.size() * 2 / 3);
    std::string flipped = good;
    flipped[good.size() / 2] ^= 0x40;
    std::ofstream(mDir.file("corrupt.tlod"), std::ios::binary) << flipped;
    std::string future = good;
    future[8] = 9;
    std::ofstream(mDir.file("future.tlod"), std::ios::binary) << future;
    std::ofstream(mDir.file("short.tlod"), std::ios::binary) << good.substr(0, 100);
  }
  TempDir mDir;
};

TEST_F(BadInputs, BuildRefusesEveryBrokenInputCleanly) {
  const std::string d = mDir.path().string();
  const std::vector<BadCase> cases = {
      {"missing file",
       {"build", d + "/nope.tif", "-o", d + "/out.tlod"},
       d + "/nope.tif: no such file"},
      {"directory", {"build", d, "-o", d + "/out.tlod"}, "is a directory"},
      {"empty file",
       {"build", d + "/empty.tif", "-o", d + "/out.tlod"},
       "empty.tif: file is empty"},
      {"non-raster",
       {"build", d + "/notes.txt", "-o", d + "/out.tlod"},
       "notes.txt: not a raster GDAL can read"},
      {"1x1 raster",
       {"build", d + "/one.tif", "-o", d + "/out.tlod"},
       "one.tif: raster is 1x1 samples"},
      {"all nodata",
       {"build", d + "/allvoid.tif", "-o", d + "/out.tlod"},
       "allvoid.tif: every sample is nodata"},
      {"truncated GeoTIFF",
       {"build", d + "/truncated.tif", "-o", d + "/out.tlod"},
       "truncated.tif: cannot read raster rows"},
      {"missing output dir",
       {"build", testData("crater_lake_0513.bt"), "-o", d + "/no/dir/out.tlod"},
       "does not exist"},
      {"unwritable output",
       {"build", testData("crater_lake_0513.bt"), "-o", "/proc/out.tlod"},
       "/proc/out.tlod: cannot write"},
      {"output is a directory",
       {"build", testData("crater_lake_0513.bt"), "-o", d},
       "is a directory"},
      {"bad chunk size",
       {"build", testData("crater_lake_0513.bt"), "-o", d + "/out.tlod", "--chunk-cells", "48"},
       "--chunk-cells must be a power of two"},
      {"error too fine",
       {"build", testData("crater_lake_0513.bt"), "-o", d + "/out.tlod", "--max-error", "0.000001"},
       "too fine for 16-bit heights"},
      {"wrong encoding",
       {"build", testData("crater_lake_0513.bt"), "-o", d + "/out.tlod", "--encoding", "terrarium"},
       "RGB-encoded heights need 3 byte bands"},
  };
  const std::vector<std::string> before = filesIn(mDir.path());
  for (const BadCase& c : cases) {
    SCOPED_TRACE(c.name);
    expectOneErrorLine(runTerralod(c.args), c.expected);
    EXPECT_EQ(filesIn(mDir.path()), before) << "partial output left behind";
  }
}

TEST_F(BadInputs, ReadersRefuseBrokenTilesetsCleanly) {
  const std::string d = mDir.path().string();
  for (const std::string command : {"info", "verify"}) {
    auto args = [&](const std::string& file) {
      std::vector<std::string> a = {command, d + "/" + file};
      if (command == "verify")
        a.insert(a.end(), {"--source", testData("gzcommon_dem_squared_129.tif")});
      return a;
    };
    SCOPED_TRACE(command);
    expectOneErrorLine(runTerralod(args("missing.tlod")), "missing.tlod: no such file");
    expectOneErrorLine(runTerralod(args("truncated.tlod")), "truncated.tlod: tileset is truncated");
    expectOneErrorLine(runTerralod(args("short.tlod")), "short.tlod: file is too short");
    expectOneErrorLine(runTerralod(args("future.tlod")),
                       "future.tlod: tileset format version 9 is not supported");
    expectOneErrorLine(runTerralod(args("notes.txt")), "notes.txt: file is too short");
  }
  // A flipped byte inside a chunk is found by verify's checksums (info reads no chunk data).
  const RunResult r = runTerralod(
      {"verify", d + "/corrupt.tlod", "--source", testData("gzcommon_dem_squared_129.tif")});
  EXPECT_EQ(r.exitCode, 1);
  EXPECT_NE(r.err.find("corrupt"), std::string::npos) << r.err;
}

TEST_F(BadInputs, VerifyRefusesTheWrongSource) {
  expectOneErrorLine(
      runTerralod({"verify", mDir.file("good.tlod"), "--source", testData("crater_lake_0513.bt")}),
      "crater_lake_0513.bt: is 513x513 samples but the tileset was built from 129x129");
}

TEST_F(BadInputs, SynthRefusesBadRequestsCleanly) {
  const std::string d = mDir.path().string();
  const std::vector<BadCase> cases = {
      {"absurd size", {"synth", "--size", "100000", "-o", d + "/s.tif"}, "outside 2..65537"},
      {"tiny size", {"synth", "--size", "1", "-o", d + "/s.tif"}, "outside 2..65537"},
      {"missing output dir",
       {"synth", "--size", "64", "-o", d + "/no/dir/s.tif"},
       d + "/no/dir/s.tif: cannot create file"},
      {"unwritable output", {"synth", "--size", "64", "-o", "/proc/s.tif"}, "/proc/s.tif"},
  };
  const std::vector<std::string> before = filesIn(mDir.path());
  for (const BadCase& c : cases) {
    SCOPED_TRACE(c.name);
    expectOneErrorLine(runTerralod(c.args), c.expected);
    EXPECT_EQ(filesIn(mDir.path()), before) << "partial output left behind";
  }
}

TEST_F(BadInputs, BuildRefusesBadTextureImagesCleanly) {
  const std::string d = mDir.path().string();
  const std::string dem = testData("zion_srtm3_utm12_30m.tif"), out = d + "/t.tlod";
  {
    std::ofstream junk(d + "/junk.tif", std::ios::binary);
    for (int i = 0; i < 4096; ++i) junk.put(char((i * 7919) % 251));
  }
  // A raster in a local (engineering) CRS: no transformation to UTM exists.
  ASSERT_EQ(runTerralod({"synth", "--size", "65", "-o", d + "/local.tif"}).exitCode, 0);
  auto texture = [&](const std::string& image) {
    return std::vector<std::string>{"build", dem, "--texture", image, "-o", out};
  };
  const std::vector<BadCase> cases = {
      {"missing image", texture(d + "/none.tif"), d + "/none.tif: no such file"},
      {"corrupt image", texture(d + "/junk.tif"), d + "/junk.tif: cannot be read as an image"},
      {"no georeferencing", texture(testData("loadersgl_terrarium_256.png")),
       "loadersgl_terrarium_256.png: has no georeferencing, so it cannot be placed on the DEM"},
      {"no overlap", texture(testData("N43W123.hgt")),
       "N43W123.hgt: does not overlap the DEM zion_srtm3_utm12_30m.tif"},
      {"no transformation", texture(d + "/local.tif"),
       "local.tif: cannot be transformed from its coordinate system to the DEM's"},
      {"contradiction",
       {"build", dem, "--texture", d + "/local.tif", "--no-texture", "-o", out},
       "--texture and --no-texture contradict each other"},
      {"min tau", {"build", dem, "--min-tau", "0", "-o", out}, "--min-tau"},
      {"bake without texture",
       {"build", dem, "--bake-colour", "--no-texture", "-o", out},
       "--bake-colour and --no-texture contradict each other"},
      {"bake an image",
       {"build", dem, "--bake-colour", "--texture", testData("zion_landsat8_rgb_utm12_30m.tif"),
        "-o", out},
       "--bake-colour applies to the generated colour (a draped image is stored as it is)"},
      {"bake materials",
       {"build", dem, "--bake-colour", "--kind", "vipm", "-o", out},
       "--bake-colour does not apply to --kind vipm (colour comes from the materials)"},
  };
  const std::vector<std::string> before = filesIn(mDir.path());
  for (const BadCase& c : cases) {
    SCOPED_TRACE(c.name);
    expectOneErrorLine(runTerralod(c.args), c.expected);
    EXPECT_EQ(filesIn(mDir.path()), before) << "partial output left behind";
  }
}

TEST_F(BadInputs, RenderRefusesBadRequestsCleanly) {
  const std::string d = mDir.path().string();
  const std::string good = d + "/good.tlod", out = d + "/out.png";
  std::ofstream(d + "/broken.json") << "{\"keyframes\": [{\"eye\": [0, 0, 1]";
  std::ofstream(d + "/short.json")
      << R"({"keyframes": [{"eye": [0, 0, 100], "target": [1, 1, 0]}]})";
  const std::vector<BadCase> cases = {
      {"future version", {"render", d + "/future.tlod", "-o", out}, "version 9 is not supported"},
      {"truncated tileset", {"render", d + "/truncated.tlod", "-o", out}, "tileset is truncated"},
      {"eye equals target",
       {"render", good, "-o", out, "--eye", "1,2,3", "--target", "1,2,3"},
       "eye and target must be different points"},
      {"non-finite eye",
       {"render", good, "-o", out, "--eye", "nan,2,3", "--target", "1,2,3"},
       "--eye must be X,Y,Z"},
      {"zero-size viewport", {"render", good, "-o", out, "--size", "0x0"}, "--size must be"},
      {"tau not positive", {"render", good, "-o", out, "--tau", "0"}, "--tau"},
      {"malformed flight",
       {"render", good, "--flight", d + "/broken.json", "--frames-dir", d},
       "broken.json: flight is not valid JSON"},
      {"one keyframe",
       {"render", good, "--flight", d + "/short.json", "--frames-dir", d},
       "short.json: flight needs \"keyframes\": an array of at least two"},
      {"bad colour", {"render", good, "-o", out, "--background", "blue"}, "--background must be"},
      {"sun below", {"render", good, "-o", out, "--sun", "10,-95"}, "--sun must be AZ,EL"},
      {"no EGL display", {"render", good, "-o", out}, "no EGL display available"},
  };
  const std::vector<std::string> before = filesIn(mDir.path());
  for (const BadCase& c : cases) {
    SCOPED_TRACE(c.name);
    // No EGL vendor library at all: what a machine without GL drivers looks like.
    const std::vector<std::string> env =
        c.name == "no EGL display"
            ? std::vector<std::string>{"__EGL_VENDOR_LIBRARY_FILENAMES=/nonexistent.json"}
            : std::vector<std::string>{};
    expectOneErrorLine(runTerralod(c.args, env), c.expected);
    EXPECT_EQ(filesIn(mDir.path()), before) << "partial output left behind";
  }
}

TEST_F(BadInputs, UsageErrorsAreOneLineToo) {
  const RunResult r = runTerralod({"build", testData("crater_lake_0513.bt")});
  EXPECT_NE(r.exitCode, 0);
  const auto lines = r.errLines();
  ASSERT_EQ(lines.size(), 1u) << r.err;
  EXPECT_NE(lines[0].find("--output is required"), std::string::npos) << lines[0];
}

}  // namespace
}  // namespace terralod::test
