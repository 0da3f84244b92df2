#include "vipm_chunk_check.h"

#include <gtest/gtest.h>

#include <algorithm>

#include "terralod/build/vipm_chunks.h"
#include "terralod/materials/material.h"
#include "terralod/vipm/collapse_order.h"
#include "terralod/vipm/progressive_mesh.h"
#include "terralod/vipm/vipm_storage.h"
#include "vipm_test_patches.h"

namespace terralod {
namespace {

struct Made {
  GridPatch patch;
  Heightfield source;
  VipmChunkData chunk;
};

// A 33-point window of Crater Lake's rim (three height-band materials), stored as the
// builder stores a chunk.
Made make(MaterialRules rules) {
  Made m;
  m.patch = test::demPatch("crater_lake_0513.bt", 192, 192, 1900, 2050, 33);
  m.source = Heightfield(m.patch.width, m.patch.height);
  std::copy(m.patch.heights.begin(), m.patch.heights.end(), m.source.values().begin());
  const HeightQuantisation q = chooseQuantisation(m.patch, 1.0);
  quantiseVertexHeights(m.patch, q);
  const ProgressiveMesh mesh =
      makeProgressiveMesh(m.patch, buildCollapseOrder(m.patch, rules), 1.0);
  m.chunk = packChunk(m.patch, mesh, q);
  return m;
}

bool mentions(const VipmChunkCheck& c, const std::string& text) {
  return std::any_of(c.problems.begin(), c.problems.end(),
                     [&](const std::string& p) { return p.find(text) != std::string::npos; });
}

TEST(VipmChunkCheck, AStoredChunkPassesAtEveryLevel) {
  const Made m = make(MaterialRules::kOn);
  const VipmChunkCheck c = checkVipmChunk(m.chunk, 0, 0, m.source, nullptr, MaterialRules::kOn);
  EXPECT_TRUE(c.problems.empty()) << c.problems.front();
  EXPECT_EQ(c.levels, m.chunk.collapseCount() + 1);
  EXPECT_GT(m.chunk.collapseCount(), 100u);
  EXPECT_EQ(c.uncovered, 0u);
  EXPECT_EQ(c.ruleViolations, 0u);
  EXPECT_EQ(c.partLevelsChecked, 3u);
  EXPECT_GE(c.worstMargin, -1e-3);
  EXPECT_LE(c.finestError, 1.0 + 1e-3);
  // The side envelopes hold the corners exactly (corners never move).
  EXPECT_EQ(c.sides[0].low.front(), c.sides[0].high.front());
  for (const SideEnvelope& s : c.sides)
    for (size_t k = 0; k < s.low.size(); ++k) EXPECT_LE(s.low[k], s.high[k]);
}

TEST(VipmChunkCheck, FindsErrorsRecordedTooSmall) {
  Made m = make(MaterialRules::kOn);
  std::fill(m.chunk.errors.begin(), m.chunk.errors.end(), uint16_t(0));
  const VipmChunkCheck c = checkVipmChunk(m.chunk, 0, 0, m.source, nullptr, MaterialRules::kOn);
  EXPECT_TRUE(mentions(c, "true error")) << (c.problems.empty() ? "" : c.problems.front());
  EXPECT_LT(c.worstMargin, -1.0);
}

TEST(VipmChunkCheck, FindsHeightsThatAreNotTheSources) {
  Made m = make(MaterialRules::kOn);
  m.source(0, 0) += 5.0f;  // a corner: never collapsed, so at every level
  const VipmChunkCheck c = checkVipmChunk(m.chunk, 0, 0, m.source, nullptr, MaterialRules::kOn);
  EXPECT_TRUE(mentions(c, "level 0: true error"));
}

TEST(VipmChunkCheck, CountsRuleBreaksAndFailsThemOnlyWhenPromised) {
  const Made m = make(MaterialRules::kOff);
  const VipmChunkCheck promised =
      checkVipmChunk(m.chunk, 0, 0, m.source, nullptr, MaterialRules::kOn);
  EXPECT_GT(promised.ruleViolations, 10u);
  EXPECT_TRUE(mentions(promised, "breaks material rule"));
  const VipmChunkCheck notPromised =
      checkVipmChunk(m.chunk, 0, 0, m.source, nullptr, MaterialRules::kOff);
  EXPECT_EQ(notPromised.ruleViolations, promised.ruleViolations);
  EXPECT_TRUE(notPromised.problems.empty()) << notPromised.problems.front();
}

TEST(VipmChunkCheck, ComparesVertexMaterialsWithTheSources) {
  const Made m = make(MaterialRules::kOn);
  MaterialMap map;
  map.columns = m.patch.width;
  map.rows = m.patch.height;
  map.classes = m.patch.materials;
  map.materials.resize(3);
  EXPECT_EQ(checkVipmChunk(m.chunk, 0, 0, m.source, &map, MaterialRules::kOn).materialMismatches,
            0u);
  map.classes[0] = uint8_t((map.classes[0] + 1) % 3);  // the south-west corner is a vertex
  const VipmChunkCheck c = checkVipmChunk(m.chunk, 0, 0, m.source, &map, MaterialRules::kOn);
  EXPECT_EQ(c.materialMismatches, 1u);
  EXPECT_TRUE(mentions(c, "another material"));
}

// A 65-point window of the rim as one leaf's normal map, as the builder stores it.
TEST(VipmNormalMapCheck, TheBuildersMapPassesAndAnotherSurfacesFails) {
  const GridPatch patch = test::demPatch("crater_lake_0513.bt", 192, 192, 1900, 2050, 65);
  Heightfield source(65, 65);
  std::copy(patch.heights.begin(), patch.heights.end(), source.values().begin());
  auto layer = [&](const Heightfield& h) {
    return decodeVipmNormalMap(buildVipmNormalMap(h, 0, 0, 64, 10.0, 10.0), 64, "t").value();
  };
  const NormalMapCheck good = checkVipmNormalMap(layer(source), 0, 0, source, 10.0, 10.0);
  EXPECT_EQ(good.problem, "");
  EXPECT_EQ(good.texels, 65u * 65u);
  EXPECT_GT(good.worst, 0.0);  // BC5 loses something on a crater rim
  EXPECT_LT(good.worst, 0.2);
  // The map of a smoother surface (what a coarse mesh would give), or at other spacings.
  Heightfield smooth = source;
  for (int32_t y = 0; y < 65; ++y)
    for (int32_t x = 0; x < 65; ++x)
      smooth(x, y) = 0.25f * (source.at(x - 2, y) + source.at(x + 2, y) + source.at(x, y - 2) +
                              source.at(x, y + 2));
  EXPECT_NE(checkVipmNormalMap(layer(smooth), 0, 0, source, 10.0, 10.0).problem, "");
  EXPECT_NE(checkVipmNormalMap(layer(source), 0, 0, source, 10.0, 20.0).problem, "");
  EXPECT_NE(checkVipmNormalMap(layer(source), 1, 0, source, 10.0, 10.0).problem, "");
}

}  // namespace
}  // namespace terralod
