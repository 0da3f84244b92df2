// The staged build's plan.json is read by every job, possibly of another terralod build on
// another node: its fields are frozen (tests/data/golden/build_plan/v6.json).

#include "terralod/build/build_plan.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>

namespace terralod {
namespace {

std::string golden() {
  std::ifstream in(std::string(TERRALOD_SOURCE_DIR) + "/tests/data/golden/build_plan/v6.json");
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

BuildPlan example() {
  BuildPlan plan;
  plan.options.input = "/data/dem.tif";
  plan.options.output = "/data/dem.tlod";
  plan.options.maxError = 0.5;
  plan.options.chunkCells = 64;
  plan.options.memoryMB = 8;
  plan.options.compressionLevel = 5;
  plan.options.dem.spacing = std::array<double, 2>{30.0, 30.0};
  plan.options.dem.verticalScale = 2.0;
  plan.options.textureImage = "/data/ortho.tif";
  plan.options.textureTau = 1.5;
  plan.options.mesher = MeshMethod::kGreedy;
  plan.options.generatedColour = GeneratedColour::kBaked;
  plan.options.chunkCodec = ChunkCodec::kMeshopt;
  plan.blockCells = 256;
  plan.heightLo = -10.5;
  plan.heightHi = 2500.25;
  plan.exactRange = false;
  plan.attempt = 1;
  plan.jobs = 2;
  plan.blocks = {{0, 0}, {1, 0}, {0, 1}};
  DemInfo& info = plan.source.info;
  info.path = "/data/dem.tif";
  info.columns = 513;
  info.rows = 257;
  info.spacingX = 30.0;
  info.spacingY = 29.5;
  info.spacingSource = "--spacing";
  info.heightScale = 0.5;
  info.heightOffset = -3.25;
  info.nodata = -32768.0;
  info.dataType = "Int16";
  info.driver = "GTiff";
  info.crsWkt = "LOCAL_CS[\"here\"]";
  info.earthCrsWkt = "";
  info.geoTransform = {100.0, 30.0, 0.0, 5000.0, 0.0, -29.5};
  info.hasGeoTransform = true;
  info.bandCount = 3;
  info.band = 2;
  plan.source.rowLatitudes = {45.0, 45.000265, 45.00053};
  plan.source.imageRefine = 4;
  return plan;
}

TEST(BuildPlan, WritesTheFrozenFields) {
  const std::string text = golden();
  ASSERT_FALSE(text.empty());
  EXPECT_EQ(buildPlanJson(example()), text);
}

TEST(BuildPlan, ReadsTheFrozenFields) {
  auto plan = parseBuildPlan(golden(), "v6.json");
  ASSERT_TRUE(plan.ok()) << plan.error().message;
  EXPECT_EQ(buildPlanJson(*plan), golden());
  EXPECT_EQ(plan->options.input, "/data/dem.tif");
  EXPECT_EQ(plan->blocks.size(), 3u);
  EXPECT_EQ(plan->jobBlocks(0), (std::array<size_t, 2>{0, 1}));
  EXPECT_EQ(plan->jobBlocks(1), (std::array<size_t, 2>{1, 3}));
  ASSERT_TRUE(plan->options.dem.spacing.has_value());
  EXPECT_EQ((*plan->options.dem.spacing)[0], 30.0);
  // What the stages that open no raster take from it.
  const DemInfo& info = plan->source.info;
  EXPECT_EQ(info.columns, 513);
  EXPECT_EQ(info.spacingY, 29.5);
  EXPECT_EQ(info.nodata, std::optional<double>(-32768.0));
  EXPECT_EQ(info.geoTransform[3], 5000.0);
  EXPECT_EQ(plan->source.rowLatitudes.size(), 3u);
  EXPECT_EQ(plan->source.imageRefine, 4u);
}

TEST(BuildPlan, KeepsTheSourceExactly) {
  // Doubles as written (any value), and the nodata values JSON has no number for.
  BuildPlan plan = example();
  plan.source.rowLatitudes = {0.1 + 0.2, 1.0 / 3.0, -89.99999999999997, 5e-324};
  plan.source.info.spacingX = 0.000277777777777778 * 111319.49079327357;
  for (const double nodata :
       {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity(),
        -std::numeric_limits<double>::infinity(), -3.4028234663852886e38}) {
    plan.source.info.nodata = nodata;
    auto back = parseBuildPlan(buildPlanJson(plan), "p.json");
    ASSERT_TRUE(back.ok()) << back.error().message;
    EXPECT_EQ(back->source.rowLatitudes, plan.source.rowLatitudes);
    EXPECT_EQ(back->source.info.spacingX, plan.source.info.spacingX);
    ASSERT_TRUE(back->source.info.nodata.has_value());
    if (std::isnan(nodata))
      EXPECT_TRUE(std::isnan(*back->source.info.nodata));
    else
      EXPECT_EQ(*back->source.info.nodata, nodata);
    EXPECT_EQ(buildPlanJson(*back), buildPlanJson(plan));
  }
  plan.source.info.nodata.reset();
  auto none = parseBuildPlan(buildPlanJson(plan), "p.json");
  ASSERT_TRUE(none.ok());
  EXPECT_FALSE(none->source.info.nodata.has_value());
  std::string bad = buildPlanJson(example());
  bad.replace(bad.find("-32768.0"), 8, "\"zero\"");
  EXPECT_EQ(parseBuildPlan(bad, "p.json").error().message,
            "p.json: build plan's source nodata is not a number");
}

TEST(BuildPlan, RefusesWhatIsNotAPlan) {
  EXPECT_EQ(parseBuildPlan("{", "p.json").error().message, "p.json: not a terralod build plan");
  std::string newer = golden();
  newer.replace(newer.find("\"version\": 6"), 12, "\"version\": 9");
  EXPECT_EQ(parseBuildPlan(newer, "p.json").error().message,
            "p.json: build plan version 9 (this terralod reads version 6)");
  std::string broken = golden();
  broken.replace(broken.find("\"jobs\""), 6, "\"jabs\"");
  EXPECT_NE(parseBuildPlan(broken, "p.json").error().message.find("p.json: build plan field"),
            std::string::npos);
  std::string sharing = golden();
  sharing.replace(sharing.find("\"inherit\""), 9, "\"maybe\"");
  EXPECT_EQ(parseBuildPlan(sharing, "p.json").error().message,
            "p.json: unknown texture sharing \"maybe\"");
  std::string mesher = golden();
  mesher.replace(mesher.find("\"greedy\""), 8, "\"fancy\"");
  EXPECT_EQ(parseBuildPlan(mesher, "p.json").error().message, "p.json: unknown mesher \"fancy\"");
  std::string colour = golden();
  colour.replace(colour.find("\"baked\""), 7, "\"paint\"");
  EXPECT_EQ(parseBuildPlan(colour, "p.json").error().message,
            "p.json: unknown generated colour \"paint\"");
}

}  // namespace
}  // namespace terralod
