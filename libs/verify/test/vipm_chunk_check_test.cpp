#include "vipm_chunk_check.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "terralod/build/vipm_chunks.h"
#include "terralod/core/sample_raster.h"
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

// checkVipmChunk draws each level from the one before (only around the triangles a collapse
// changed). Here every level is drawn whole, all triangles in stored order, as the check did
// before: the levels' uncovered points, worst margin and coarsest surface must be the same,
// also when collapses fold triangles over others (targets moved onto far vertices), where which
// triangle is drawn last decides a point's height.
TEST(VipmChunkCheck, LevelsDrawnCollapseByCollapseAreTheWholeDrawings) {
  for (const bool folded : {false, true}) {
    Made m = make(MaterialRules::kOn);
    const VipmChunkData& c = m.chunk;
    const uint32_t n = c.vertexCount();
    if (folded)
      for (uint32_t j = 0; j < c.collapseCount(); j += 5)
        m.chunk.targets[j] = uint16_t((j * 7919u) % (n - 1 - j));  // any vertex still there
    const VipmChunkCheck check = checkVipmChunk(c, 0, 0, m.source, nullptr, MaterialRules::kOff);

    std::vector<uint16_t> rename(n);
    for (uint32_t v = 0; v < n; ++v) rename[v] = uint16_t(v);
    const int32_t w = c.width, h = c.height;
    std::vector<double> surface;
    uint64_t uncovered = 0;
    double worstMargin = 1e30;
    for (uint32_t j = 0; j <= c.collapseCount(); ++j) {
      surface.assign(size_t(w) * h, std::numeric_limits<double>::quiet_NaN());
      for (size_t k = 0; k + 2 < c.indices.size(); k += 3) {
        const uint16_t a = rename[c.indices[k]], b = rename[c.indices[k + 1]],
                       d = rename[c.indices[k + 2]];
        if (a == b || b == d || a == d) continue;
        auto vertex = [&](uint16_t v) {
          return SampleVertex{int64_t(c.points[v] % c.width), int64_t(c.points[v] / c.width),
                              c.zBase + double(c.heights[v]) * c.zStep};
        };
        rasterizeTriangle(vertex(a), vertex(b), vertex(d), 0, w - 1, 0, h - 1,
                          [&](int64_t x, int64_t y, double z) { surface[size_t(y * w + x)] = z; });
      }
      double error = 0;
      for (int32_t y = 0; y < h; ++y)
        for (int32_t x = 0; x < w; ++x) {
          const double z = surface[size_t(y * w + x)];
          if (std::isnan(z))
            ++uncovered;
          else
            error = std::max(error, std::fabs(z - double(m.source.at(x, y))));
        }
      const double recorded = j == 0 ? c.finestError : double(c.errors[j - 1]) * c.errorStep;
      worstMargin = std::min(worstMargin, recorded - error);
      if (j == c.collapseCount()) break;
      for (uint16_t& r : rename)
        if (r == uint16_t(n - 1 - j)) r = c.targets[j];
    }
    EXPECT_EQ(check.uncovered, uncovered) << folded;
    EXPECT_EQ(check.worstMargin, worstMargin) << folded;
    ASSERT_EQ(check.coarsestHeights.size(), surface.size());
    for (size_t p = 0; p < surface.size(); ++p)
      ASSERT_TRUE(check.coarsestHeights[p] == surface[p] ||
                  (std::isnan(check.coarsestHeights[p]) && std::isnan(surface[p])))
          << folded << " point " << p;
    if (folded) {
      EXPECT_LT(check.worstMargin, -1.0) << "the folds were seen";
    }
  }
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
