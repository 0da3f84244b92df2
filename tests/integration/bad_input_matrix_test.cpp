// The bad-input matrix, per format: tilesets, rasters (GeoTIFF, PNG, RGB-encoded PNG) and
// flight files, each broken in the ways files arrive broken — empty, truncated, wrong magic,
// a version from the future, sizes no file could hold, NaN and infinite values, offsets past
// the end, chunks sharing bytes. Each gets exactly its expected line, exit status 1 and no
// output. (bad_input_test.cpp covers bad requests: options, paths, missing drivers.)

#include <gdal_priv.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>

#include "cli_expectations.h"
#include "cli_runner.h"
#include "damaged_files.h"

namespace terralod::test {
namespace {

namespace fs = std::filesystem;

struct BrokenFile {
  std::string file;         ///< in the scratch directory
  std::string problem;      ///< the line is "terralod: error: <dir>/<file>: <problem>"
  bool prefixOnly = false;  ///< the problem ends with GDAL's own words, which vary by version
};

/// Exit status 1, one line, exactly `line` (or starting with it), and no file added to `dir`.
void expectRefused(const std::vector<std::string>& args, const fs::path& dir,
                   const std::string& line, bool prefixOnly) {
  const std::vector<std::string> before = filesIn(dir);
  const RunResult r = runTerralod(args);
  EXPECT_EQ(r.exitCode, 1);
  const auto lines = r.errLines();
  ASSERT_EQ(lines.size(), 1u) << r.err;
  if (prefixOnly)
    EXPECT_EQ(lines[0].substr(0, line.size()), line);
  else
    EXPECT_EQ(lines[0], line);
  EXPECT_EQ(filesIn(dir), before) << "output left behind";
}

class BadInputMatrix : public ::testing::Test {
 protected:
  std::string at(const std::string& name) const { return mDir.file(name); }
  std::string line(const BrokenFile& b) const {
    return "terralod: error: " + at(b.file) + ": " + b.problem;
  }
  TempDir mDir;
};

TEST_F(BadInputMatrix, Tilesets) {
  const std::string good = testData("golden/v2/gully.tlod");
  const std::string bytes = readWholeFile(good);
  const uint64_t size = bytes.size();
  auto write = [&](const std::string& name, const std::string& content) {
    std::ofstream(at(name), std::ios::binary) << content;
  };
  write("empty.tlod", "");
  write("truncated.tlod", bytes.substr(0, size - 1000));
  write("magic.tlod", "TERRAIN!" + bytes.substr(8));
  std::string flipped = bytes;
  flipped[100] ^= 0x04;
  write("header_crc.tlod", flipped);
  using Nodes = std::vector<NodeRecord>;
  auto edit = [&](const std::string& name, const std::function<void(TilesetHeader&, Nodes&)>& f) {
    writeEditedTileset(good, at(name), f);
  };
  edit("future.tlod", [](TilesetHeader& h, Nodes&) { h.version = 8; });
  edit("huge_roots.tlod", [](TilesetHeader& h, Nodes&) { h.rootsX = 100000; });
  edit("huge_levels.tlod", [](TilesetHeader& h, Nodes&) { h.levelCount = 99; });
  edit("huge_source.tlod", [](TilesetHeader& h, Nodes&) { h.sourceColumns = 0xFFFFFFFF; });
  edit("huge_node_count.tlod", [](TilesetHeader& h, Nodes&) { h.nodeCount = uint64_t{1} << 40; });
  edit("huge_table_offset.tlod",
       [](TilesetHeader& h, Nodes&) { h.nodeTableOffset = ~uint64_t{0} - 100; });
  edit("nan_spacing.tlod", [](TilesetHeader& h, Nodes&) { h.spacingX = std::nan(""); });
  edit("inf_error.tlod",
       [](TilesetHeader& h, Nodes&) { h.levelError[1] = std::numeric_limits<double>::infinity(); });
  edit("nan_height.tlod", [](TilesetHeader&, Nodes& n) { n[2].minZ = std::nanf(""); });
  edit("past_end.tlod", [&](TilesetHeader&, Nodes& n) { n[3].blobOffset = size + 100; });
  edit("wrapping_offset.tlod",
       [](TilesetHeader&, Nodes& n) { n[3].blobOffset = ~uint64_t{0} - 100; });
  edit("overlap.tlod", [](TilesetHeader&, Nodes& n) { n[5].blobOffset = n[4].blobOffset + 10; });
  // A chunk starting inside the node table (the untextured golden: its chunks are small
  // enough to stay inside the file from there).
  writeEditedTileset(testData("golden/v1/gully.tlod"), at("overlap_table.tlod"),
                     [](TilesetHeader& h, Nodes& n) { n[1].blobOffset = h.nodeTableOffset + 8; });
  const TilesetHeader header =
      parseHeader(std::span(reinterpret_cast<const uint8_t*>(bytes.data()), size), good).value();
  std::string table = bytes;
  table[header.nodeTableOffset + 9] ^= 0x01;
  write("table_crc.tlod", table);

  const std::vector<BrokenFile> cases = {
      {"missing.tlod", "no such file"},
      {"empty.tlod", "file is too short to be a terralod tileset (0 bytes)"},
      {"truncated.tlod", "tileset is truncated or padded: header says " + std::to_string(size) +
                             " bytes, file has " + std::to_string(size - 1000)},
      {"magic.tlod", "not a terralod tileset (wrong magic bytes)"},
      {"future.tlod",
       "tileset format version 8 is not supported (this terralod reads versions 1 to 7)"},
      {"header_crc.tlod", "tileset header is corrupt (checksum mismatch)"},
      {"table_crc.tlod", "node table is corrupt (checksum mismatch)"},
      {"huge_roots.tlod", "invalid tileset header: root grid"},
      {"huge_levels.tlod", "invalid tileset header: level count out of range"},
      {"huge_source.tlod", "invalid tileset header: source size does not fit the root grid"},
      {"huge_node_count.tlod", "invalid tileset header: node count"},
      {"huge_table_offset.tlod", "invalid tileset header: table offsets"},
      {"nan_spacing.tlod", "invalid tileset header: spacing"},
      {"inf_error.tlod", "invalid tileset header: level error"},
      {"nan_height.tlod", "corrupt node table: node 2 has an invalid height range"},
      {"past_end.tlod", "corrupt node table: node 3 points outside the file"},
      {"wrapping_offset.tlod", "corrupt node table: node 3 points outside the file"},
      {"overlap.tlod", "corrupt node table: node 5 overlaps node 4"},
      {"overlap_table.tlod", "corrupt node table: node 1 overlaps the node table"},
  };
  for (const BrokenFile& b : cases) {
    SCOPED_TRACE(b.file);
    expectRefused({"info", at(b.file)}, mDir.path(), line(b), false);
  }
  // Every command opens tilesets through the same reader; render stands for the others.
  for (size_t i : {1, 4, 15, 17}) {
    SCOPED_TRACE(cases[i].file);
    expectRefused({"render", at(cases[i].file), "-o", at("out.png")}, mDir.path(), line(cases[i]),
                  false);
  }
  // verify reads every chunk; its source is the golden's.
  expectRefused(
      {"verify", at("overlap.tlod"), "--source", testData("landlab_west_bijou_gully_3m.asc")},
      mDir.path(), line({"overlap.tlod", "corrupt node table: node 5 overlaps node 4"}), false);
}

// A chunk whose checksum matches bytes that are not a chunk: found when it is decoded (by
// export and render; verify lists it among its failures).
TEST_F(BadInputMatrix, ChunksBehindValidChecksums) {
  const std::string good = testData("golden/v1/gully.tlod");
  std::string bytes = readWholeFile(good);
  auto* data = reinterpret_cast<uint8_t*>(bytes.data());
  const TilesetHeader h = parseHeader(std::span(data, bytes.size()), good).value();
  NodeRecord n = parseNode(data + h.nodeTableOffset, h.version);
  std::fill_n(bytes.begin() + ptrdiff_t(n.blobOffset), 8, '\x5A');  // no zstd magic any more
  n.blobCrc = crc32Of(std::span(data + n.blobOffset, n.blobBytes));
  serializeNode(n, data + h.nodeTableOffset);
  std::ofstream(at("chunk.tlod"), std::ios::binary) << bytes;
  writeEditedTileset(at("chunk.tlod"), at("chunk.tlod"), [](TilesetHeader&, auto&) {});
  const std::string expected =
      "terralod: error: " + at("chunk.tlod") + " chunk 0: corrupt chunk: not a zstd frame";
  expectRefused({"export", at("chunk.tlod"), "--level", "0", "-o", at("out.obj")}, mDir.path(),
                expected, false);
  expectRefused({"render", at("chunk.tlod"), "-o", at("out.png")}, mDir.path(), expected, false);
}

TEST_F(BadInputMatrix, Rasters) {
  const std::string tiff = testData("gzcommon_dem_squared_129.tif");
  const std::string png = testData("loadersgl_terrarium_256.png");
  const std::string tiffBytes = readWholeFile(tiff), pngBytes = readWholeFile(png);
  auto write = [&](const std::string& name, const std::string& content) {
    std::ofstream(at(name), std::ios::binary) << content;
  };
  write("empty.tif", "");
  write("empty.png", "");
  write("truncated.png", pngBytes.substr(0, 3000));
  write("magic.tif", "XX" + tiffBytes.substr(2));
  write("magic.png", "JPEG" + pngBytes.substr(4));
  writeConstantTiff(at("wide.tif"), 2000000, 2, GDT_Int16, 0);
  writePngPromising(at("huge.png"), 200000, 100000, true);  // libpng's limit: 10^6 a side
  writePngPromising(at("big.png"), 20000, 60000, true);
  writeConstantTiff(at("nan.tif"), 20, 10, GDT_Float32, std::nan(""));
  writeConstantTiff(at("inf.tif"), 20, 10, GDT_Float32, std::numeric_limits<double>::infinity());
  writeConstantTiff(at("minus_inf.tif"), 20, 10, GDT_Float32,
                    -std::numeric_limits<double>::infinity());
  writeConstantTiff(at("beyond_float.tif"), 20, 10, GDT_Float64, 1e300);
  // Made by the raster fuzzer: PROJ used to print a line of its own about the unit.
  fs::copy_file(testData("damaged/unknown_unit_code.tif"), at("unknown_unit.tif"));

  struct RasterCase {
    BrokenFile broken;
    std::vector<std::string> options;
  };
  const std::vector<std::string> terrarium = {"--encoding", "terrarium"};
  const std::string noTerrain = "every sample is nodata; there is no terrain to build";
  const std::vector<RasterCase> cases = {
      {{"empty.tif", "file is empty"}, {}},
      {{"empty.png", "file is empty"}, terrarium},
      {{"truncated.png", "cannot read raster rows 0-63 (", true}, terrarium},
      {{"magic.tif", "not a raster GDAL can read"}, {}},
      {{"magic.png", "not a raster GDAL can read"}, terrarium},
      {{"wide.tif",
        "raster is 2000000x2 samples, more than terralod supports (1048576 per side, 2^34 in "
        "all)"},
       {}},
      {{"huge.png",
        "raster is 200000x100000 samples, more than terralod supports (1048576 per side, 2^34 "
        "in all)"},
       {"--encoding", "terrain-rgb"}},
      {{"big.png", "the raster needs 4577 MB, more than --memory-mb 2048"}, terrarium},
      {{"nan.tif", noTerrain}, {}},
      {{"inf.tif", noTerrain}, {}},
      {{"minus_inf.tif", noTerrain}, {}},
      {{"beyond_float.tif", noTerrain}, {}},
      {{"unknown_unit.tif", "raster columns run east to west; warp it first (gdalwarp)"}, {}},
  };
  for (const RasterCase& c : cases) {
    SCOPED_TRACE(c.broken.file);
    std::vector<std::string> args = {"build", at(c.broken.file), "-o", at("out.tlod")};
    args.insert(args.end(), c.options.begin(), c.options.end());
    expectRefused(args, mDir.path(), line(c.broken), c.broken.prefixOnly);
  }
}

TEST_F(BadInputMatrix, Flights) {
  const std::string good = testData("golden/v2/gully.tlod");
  auto write = [&](const std::string& name, const std::string& content) {
    std::ofstream(at(name)) << content;
  };
  const std::string keys = R"([{"eye": [0, 0, 100], "target": [1, 1, 0]},
                               {"eye": [5, 0, 100], "target": [6, 1, 0]}])";
  write("empty.json", "");
  write("truncated.json", "{\"keyframes\": " + keys.substr(0, 30));
  write("huge_number.json", R"({"keyframes": [{"eye": [0, 0, 1e400], "target": [1, 1, 0]}]})");
  write("nan.json", R"({"keyframes": [{"eye": [0, 0, NaN], "target": [1, 1, 0]}]})");
  write("far_eye.json", R"({"keyframes": [{"eye": [0, 0, 100], "target": [1, 1, 0]},
                                          {"eye": [1.5e61, 0, 100], "target": [1, 1, 0]}]})");
  write("huge_frames.json", "{\"frames\": 99999999999, \"keyframes\": " + keys + "}");
  write("huge_size.json", "{\"size\": [100000, 1], \"keyframes\": " + keys + "}");
  write("zero_fov.json", "{\"fov_deg\": 0, \"keyframes\": " + keys + "}");
  write("same_point.json",
        R"({"keyframes": [{"eye": [1, 2, 3], "target": [1, 2, 3]},
                          {"eye": [5, 0, 100], "target": [6, 1, 0]}]})");
  const std::vector<BrokenFile> cases = {
      {"empty.json", "flight is not valid JSON"},
      {"truncated.json", "flight is not valid JSON"},
      {"huge_number.json", "flight is not valid JSON"},
      {"nan.json", "flight is not valid JSON"},
      {"far_eye.json", "keyframe 1 eye must be within 1e12 m of the origin"},
      {"huge_frames.json", "frames must be a whole number from 1 to 1000000"},
      {"huge_size.json", "size must be between 1x1 and 16384x16384 pixels"},
      {"zero_fov.json", "fov_deg must be between 0 and 180"},
      {"same_point.json", "keyframe 0: eye and target are the same point"},
  };
  fs::create_directory(at("frames"));
  for (const BrokenFile& b : cases) {
    SCOPED_TRACE(b.file);
    expectRefused({"render", good, "--flight", at(b.file), "--frames-dir", at("frames")},
                  mDir.path() / "frames", line(b), false);
  }
  // bench reads flights the same way.
  for (size_t i : {0, 5}) {
    SCOPED_TRACE(cases[i].file);
    expectRefused({"bench", good, "--flight", at(cases[i].file), "--json", at("bench.json")},
                  mDir.path(), line(cases[i]), false);
  }
}

// NaN and ±Inf among valid heights are voids: filled, counted, and the build succeeds.
TEST_F(BadInputMatrix, NonFiniteHeightsAmongValidOnesAreVoids) {
  GDALAllRegister();
  {
    GDALDatasetUniquePtr ds(GetGDALDriverManager()->GetDriverByName("GTiff")->Create(
        at("holes.tif").c_str(), 30, 20, 1, GDT_Float32, nullptr));
    std::vector<float> v(30 * 20);
    for (size_t i = 0; i < v.size(); ++i) v[i] = float(100 + i % 30 + i / 30);
    v[45] = std::nanf("");
    v[46] = std::numeric_limits<float>::infinity();
    v[47] = -std::numeric_limits<float>::infinity();
    ASSERT_EQ(
        ds->GetRasterBand(1)->RasterIO(GF_Write, 0, 0, 30, 20, v.data(), 30, 20, GDT_Float32, 0, 0),
        CE_None);
  }
  const RunResult built = runTerralod({"build", at("holes.tif"), "-o", at("holes.tlod")});
  ASSERT_EQ(built.exitCode, 0) << built.err;
  const RunResult info = runTerralod({"info", at("holes.tlod"), "--json"});
  EXPECT_NE(info.out.find("\"filled_voids\": 3"), std::string::npos) << info.out;
}

}  // namespace
}  // namespace terralod::test
