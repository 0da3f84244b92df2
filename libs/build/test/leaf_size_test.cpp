// The automatic leaf size: the pure rule, pass 1's estimate of the leaf triangles against the
// triangles a build really makes, and what the choice buys on smooth and rough terrain.

#include "terralod/build/leaf_size.h"

#include <gtest/gtest.h>

#include <filesystem>

#include "terralod/build/builder.h"
#include "terralod/format/tileset_reader.h"
#include "terralod/raster/dem_reader.h"
#include "terralod/raster/synthetic_dem_writer.h"

namespace terralod {
namespace {

namespace fs = std::filesystem;

TEST(AutomaticLeafCells, SmallRootsKeepSixtyFourCells) {
  EXPECT_EQ(automaticLeafCells(512, 1.0), 64);  // 128-cell leaves would leave three levels
  EXPECT_EQ(automaticLeafCells(256, 1.0), 64);  // never below 64 (leafCellsFor gives 0 here)
}

TEST(AutomaticLeafCells, GrowsUntilLeavesHoldTheTarget) {
  EXPECT_EQ(automaticLeafCells(8192, kTargetLeafTriangles), 64);
  EXPECT_EQ(automaticLeafCells(8192, 1000.0), 64);
  EXPECT_EQ(automaticLeafCells(8192, 159.0), 64);
  EXPECT_EQ(automaticLeafCells(8192, 40.0), 128);  // 160 at 128
  EXPECT_EQ(automaticLeafCells(8192, 18.0), 256);  // 72 at 128, 288 at 256
  EXPECT_EQ(automaticLeafCells(8192, 0.0), 256);   // flat: as large as allowed
  // At most rootCells / 8.
  EXPECT_EQ(automaticLeafCells(1024, 1.0), 128);
  EXPECT_EQ(automaticLeafCells(2048, 1.0), 256);
}

class LeafSize : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    char name[] = "/tmp/terralod-leaf-size-XXXXXX";
    sDir = mkdtemp(name);
    NullProgress progress;
    // The same fractal at 5 m (rough at 1 m error: about 300 triangles per 64-cell leaf) and
    // at 2 m (gentle: about 30).
    for (const auto& [file, spacing] :
         {std::pair{"rough.tif", 5.0}, std::pair{"gentle.tif", 2.0}}) {
      SyntheticDemOptions o;
      o.output = (sDir / file).string();
      o.columns = o.rows = 2049;
      o.spacing = spacing;
      o.threads = 2;
      ASSERT_TRUE(writeSyntheticDem(o, progress).ok());
    }
  }
  static void TearDownTestSuite() { fs::remove_all(sDir); }

  static std::string file(const std::string& name) { return (sDir / name).string(); }

  // Builds `dem` untextured at 1 m; returns the tileset's path.
  static std::string build(const std::string& dem, int32_t chunkCells) {
    BuildOptions options;
    options.input = file(dem);
    options.output = file(dem + "." + std::to_string(chunkCells) + ".tlod");
    options.maxError = 1.0;
    options.textures = false;
    options.threads = 2;
    options.chunkCells = chunkCells;
    NullProgress progress;
    auto summary = buildTileset(options, progress, [](const std::string&) {});
    EXPECT_TRUE(summary.ok()) << (summary ? "" : summary.error().message);
    return options.output;
  }

  static inline fs::path sDir;
};

TEST_F(LeafSize, TheEstimateIsNearTheLeafTrianglesABuildMakes) {
  for (const char* dem : {"rough.tif", "gentle.tif"}) {
    SCOPED_TRACE(dem);
    auto reader = DemReader::open(file(dem), {});
    ASSERT_TRUE(reader.ok()) << reader.error().message;
    auto estimate = estimateLeafTriangles(**reader, 1.0);
    ASSERT_TRUE(estimate.ok()) << estimate.error().message;
    EXPECT_EQ(estimate->blocks, 16);
    auto twoThreads = estimateLeafTriangles(**reader, 1.0, 2);
    ASSERT_TRUE(twoThreads.ok()) << twoThreads.error().message;
    EXPECT_EQ(twoThreads->blocks, 16);
    EXPECT_EQ(twoThreads->trianglesPer64, estimate->trianglesPer64);
    auto t = TilesetReader::openFile(build(dem, 64));
    ASSERT_TRUE(t.ok()) << t.error().message;
    const uint32_t leaf = (*t)->header().levelCount - 1;
    uint64_t triangles = 0, chunks = 0;
    for (const NodeRecord& n : (*t)->nodes())
      if (n.level == leaf) {
        triangles += n.triangleCount;
        ++chunks;
      }
    const double perLeaf = double(triangles) / double(chunks);
    EXPECT_GT(estimate->trianglesPer64, 0.7 * perLeaf) << perLeaf;
    EXPECT_LT(estimate->trianglesPer64, 1.3 * perLeaf) << perLeaf;
  }
}

TEST_F(LeafSize, GentleTerrainGetsLargerLeavesAndASmallerFile) {
  auto leaves = [](const std::string& path) {
    auto t = TilesetReader::openFile(path);
    EXPECT_TRUE(t.ok());
    return t ? int32_t((*t)->header().leafCells) : 0;
  };
  const std::string gentle = build("gentle.tif", 0), rough = build("rough.tif", 0);
  EXPECT_EQ(leaves(rough), 64);    // its 64-cell leaves hold enough
  EXPECT_EQ(leaves(gentle), 128);  // about 110 at 128
  // What the larger leaves buy: the same bound in fewer bytes than 64-cell leaves.
  EXPECT_LT(fs::file_size(gentle), fs::file_size(build("gentle.tif", 64)) * 7 / 10);
}

}  // namespace
}  // namespace terralod
