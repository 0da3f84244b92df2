// The staged build's plan.json is read by every job, possibly of another terralod build on
// another node: its fields are frozen (tests/data/golden/build_plan/v5.json).

#include "terralod/build/build_plan.h"

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

namespace terralod {
namespace {

std::string golden() {
  std::ifstream in(std::string(TERRALOD_SOURCE_DIR) + "/tests/data/golden/build_plan/v5.json");
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
  return plan;
}

TEST(BuildPlan, WritesTheFrozenFields) {
  const std::string text = golden();
  ASSERT_FALSE(text.empty());
  EXPECT_EQ(buildPlanJson(example()), text);
}

TEST(BuildPlan, ReadsTheFrozenFields) {
  auto plan = parseBuildPlan(golden(), "v5.json");
  ASSERT_TRUE(plan.ok()) << plan.error().message;
  EXPECT_EQ(buildPlanJson(*plan), golden());
  EXPECT_EQ(plan->options.input, "/data/dem.tif");
  EXPECT_EQ(plan->blocks.size(), 3u);
  EXPECT_EQ(plan->jobBlocks(0), (std::array<size_t, 2>{0, 1}));
  EXPECT_EQ(plan->jobBlocks(1), (std::array<size_t, 2>{1, 3}));
  ASSERT_TRUE(plan->options.dem.spacing.has_value());
  EXPECT_EQ((*plan->options.dem.spacing)[0], 30.0);
}

TEST(BuildPlan, RefusesWhatIsNotAPlan) {
  EXPECT_EQ(parseBuildPlan("{", "p.json").error().message, "p.json: not a terralod build plan");
  std::string newer = golden();
  newer.replace(newer.find("\"version\": 5"), 12, "\"version\": 9");
  EXPECT_EQ(parseBuildPlan(newer, "p.json").error().message,
            "p.json: build plan version 9 (this terralod reads version 5)");
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
