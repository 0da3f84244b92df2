// `terralod verify` on VIPM tilesets: a tileset `build --kind vipm` wrote passes every check
// (each LOD's true error, the material rules, parts, fallback roots, flanges); the rules are
// failures only when the tileset promises them; a source that is not the one it was built
// from fails; so does a normal map that is not the source's, and a damaged one is one clear
// line (verify) or a load failure logged once (render).

#include <gdal_priv.h>
#include <gtest/gtest.h>

#include <fstream>

#include "terralod/format/tileset_reader.h"
#include "terralod/format/vipm_chunk_codec.h"

#include "cli_expectations.h"
#include "cli_runner.h"
#include "damaged_files.h"

namespace terralod::test {
namespace {

const std::string kVerifyDem = testData("gzcommon_dem_squared_129.tif");

class VipmVerifyCli : public ::testing::Test {
 protected:
  TempDir mDir;
};

TEST_F(VipmVerifyCli, ABuiltTilesetPassesEveryCheck) {
  const std::string out = mDir.file("v.tlod");
  ASSERT_EQ(
      runTerralod({"build", kVerifyDem, "--kind", "vipm", "--threads", "2", "-o", out}).exitCode,
      0);
  const RunResult verified = runTerralod({"verify", out, "--source", kVerifyDem, "--threads", "2"});
  EXPECT_EQ(verified.exitCode, 0) << verified.out << verified.err;
  EXPECT_TRUE(has(verified.out, "verify: OK")) << verified.out;
  EXPECT_TRUE(has(verified.out, ", 0 break a material rule (built with the rules)"))
      << verified.out;
  EXPECT_TRUE(has(verified.out, "vertex materials against the source's: 0 differ")) << verified.out;
  EXPECT_TRUE(has(verified.out, "largest difference 0.000000 m")) << verified.out;
  EXPECT_TRUE(has(verified.out, "normal maps: 5 (")) << verified.out;  // 1 root, 4 leaves
}

// --blot-error: leaves stop at it, the root takes over at twice it and simplifies further
// without the rules; verify checks the root's LODs (not against the rules), its first
// collapse against the roots' level error, and its flanges over its children's shared sides.
TEST_F(VipmVerifyCli, BlotRootsPassEveryCheck) {
  const std::string out = mDir.file("b.tlod");
  const RunResult built = runTerralod(
      {"build", kVerifyDem, "--kind", "vipm", "--blot-error", "2", "--threads", "2", "-o", out});
  ASSERT_EQ(built.exitCode, 0) << built.err;
  auto reader = TilesetReader::openFile(out).value();
  EXPECT_LE(reader->header().levelError[0], 4.0);
  auto root = decodeVipmChunk(reader->readBlob(0).value(), "root").value();
  EXPECT_GT(root.collapseCount(), 100u);  // a blot chunk
  EXPECT_GE(double(root.errors.front()) * root.errorStep, reader->header().levelError[0]);
  const RunResult verified = runTerralod({"verify", out, "--source", kVerifyDem, "--threads", "2"});
  EXPECT_EQ(verified.exitCode, 0) << verified.out << verified.err;
  EXPECT_TRUE(has(verified.out, "verify: OK")) << verified.out;
  EXPECT_TRUE(has(verified.out, ", 0 break a material rule (built with the rules)"))
      << verified.out;

  // The root's flanges made too shallow for the gap between its children's sides.
  const std::string shallow = mDir.file("shallow.tlod");
  writeEditedTileset(
      out, shallow, [](TilesetHeader&, std::vector<NodeRecord>& n) { n[0].maxSkirtDepth = 0.01f; });
  const RunResult caught =
      runTerralod({"verify", shallow, "--source", kVerifyDem, "--threads", "2"});
  EXPECT_EQ(caught.exitCode, 1) << caught.out << caught.err;
  EXPECT_TRUE(has(caught.err + caught.out, "do not close the gap between its children's sides"))
      << caught.out << caught.err;
}

// Overwrites `bytes` at `offset` of node `node`'s texture blob; with `fixCrc` the blob's own
// checksum is made to match again (so only the texels are wrong).
void damageTexture(const std::string& path, uint32_t node, size_t offset,
                   const std::vector<uint8_t>& bytes, bool fixCrc) {
  auto reader = TilesetReader::openFile(path).value();
  auto read = reader->readNode(node).value();
  std::vector<uint8_t> texture(read.texture().begin(), read.texture().end());
  std::copy(bytes.begin(), bytes.end(), texture.begin() + std::ptrdiff_t(offset));
  if (fixCrc) {
    const uint32_t crc = crc32Of(std::span<const uint8_t>(texture).subspan(12));
    for (int i = 0; i < 4; ++i) texture[8 + size_t(i)] = uint8_t(crc >> (8 * i));
  }
  const NodeRecord& n = reader->nodes()[node];
  std::fstream f(path, std::ios::in | std::ios::out | std::ios::binary);
  f.seekp(std::streamoff(n.blobOffset + n.blobBytes));
  f.write(reinterpret_cast<const char*>(texture.data()), std::streamsize(texture.size()));
}

TEST_F(VipmVerifyCli, NormalMapsThatAreNotTheSourcesOrAreDamagedFail) {
  const std::string out = mDir.file("v.tlod");
  // Without blot roots, so the render below draws the leaves.
  ASSERT_EQ(runTerralod({"build", kVerifyDem, "--kind", "vipm", "--blot-error", "off", "-o", out})
                .exitCode,
            0);
  // Leaf 1's first mip 0 block row: both channels' end points swapped to 0 and 255.
  const std::string wrong = mDir.file("wrong.tlod");
  std::filesystem::copy_file(out, wrong);
  std::vector<uint8_t> extremes;
  for (int b = 0; b < 17 * 2; ++b) extremes.insert(extremes.end(), {0, 255, 0, 0, 0, 0, 0, 0});
  damageTexture(wrong, 1, 32, extremes, true);
  const RunResult verified = runTerralod({"verify", wrong, "--source", kVerifyDem});
  EXPECT_EQ(verified.exitCode, 1);
  EXPECT_TRUE(has(verified.err, "chunk 1 (level 1, 0,0): its normal map's texel ("))
      << verified.err;

  // Its checksum no longer matching: verify says so, render logs it once and still draws.
  const std::string damaged = mDir.file("damaged.tlod");
  std::filesystem::copy_file(out, damaged);
  damageTexture(damaged, 1, 40, {0x5A}, false);
  const RunResult checked = runTerralod({"verify", damaged, "--source", kVerifyDem});
  EXPECT_EQ(checked.exitCode, 1);
  EXPECT_TRUE(
      has(checked.err, "damaged.tlod: chunk 1 (level 1, 0,0): invalid texture: checksum mismatch"))
      << checked.err;
  const RunResult rendered =
      runTerralod({"render", damaged, "-o", mDir.file("r.png"), "--size", "160x120"});
  EXPECT_EQ(rendered.exitCode, 0) << rendered.err;
  size_t lines = 0;
  for (size_t at = 0; (at = rendered.err.find("invalid texture", at)) != std::string::npos; ++at)
    ++lines;
  EXPECT_EQ(lines, 1u) << rendered.err;
}

TEST_F(VipmVerifyCli, RuleBreaksFailOnlyATilesetBuiltWithTheRules) {
  const std::string out = mDir.file("norules.tlod");
  ASSERT_EQ(runTerralod({"build", kVerifyDem, "--kind", "vipm", "--no-material-rules", "-o", out})
                .exitCode,
            0);
  const RunResult verified = runTerralod({"verify", out, "--source", kVerifyDem});
  EXPECT_EQ(verified.exitCode, 0) << verified.err;
  EXPECT_TRUE(has(verified.out, "(built with --no-material-rules)")) << verified.out;
  EXPECT_FALSE(has(verified.out, ", 0 break a material rule")) << verified.out;
}

TEST_F(VipmVerifyCli, FailsAgainstASourceItWasNotBuiltFrom) {
  const std::string out = mDir.file("v.tlod");
  ASSERT_EQ(runTerralod({"build", kVerifyDem, "--kind", "vipm", "-o", out}).exitCode, 0);
  // The same DEM with a 3 m bump in one corner.
  const std::string bumped = mDir.file("bumped.tif");
  GDALAllRegister();
  {
    GDALDatasetUniquePtr dem(GDALDataset::Open(kVerifyDem.c_str(), GDAL_OF_RASTER));
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
