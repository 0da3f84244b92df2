// Chunk payload version 2 (docs/format.md "Derived skirts"): what a reader derives from the
// surface and each side's depth is the skirt version 1 stores, triangle for triangle, with
// every bottom at most one height step deeper and never shallower.

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdlib>
#include <map>
#include <random>

#include "chunk_triangles.h"
#include "terralod/build/activation_pass.h"
#include "terralod/build/chunk_encoder.h"
#include "terralod/build/chunk_mesher.h"
#include "test_terrain.h"

namespace terralod {
namespace {

ChunkGeometry roundTrip(const ChunkMesh& mesh, const ErrorBudget& budget,
                        ChunkPayloadVersion payload) {
  const ChunkGeometry quantized = quantizeChunk(mesh, budget, payload).value();
  auto decoded = decodeChunk(encodeChunk(quantized, 3, payload), "chunk");
  EXPECT_TRUE(decoded.ok()) << decoded.error().message;
  return decoded.ok() ? *decoded : ChunkGeometry{};
}

double worldZ(const ChunkGeometry& g, const ChunkVertex& v) {
  return g.zBase + v.z * g.zStep;
}

class DerivedSkirts : public ::testing::TestWithParam<std::tuple<int, int, uint32_t>> {};

TEST_P(DerivedSkirts, AreTheStoredSkirtsNeverShallowerAndAtMostAStepDeeper) {
  const auto [columns, rows, seed] = GetParam();
  const Heightfield heights = test::makeTestTerrain(columns, rows, seed);
  const TreeLayout layout = makeTreeLayout(columns, rows, 16).value();
  const ErrorBudget budget = makeErrorBudget(layout, 0.5, 400.0).value();
  MemoryHeights memory(heights);
  NullProgress progress;
  ActivationOptions options;
  options.blockCells = 32;
  const ActivationGrid grid =
      computeActivations(layout, budget, memory, memory, options, progress).value();
  ChunkMesher mesher(layout, budget, grid, memory);
  size_t skirted = 0;
  for (int32_t l = 0; l <= layout.depth; ++l)
    for (int32_t iy = 0; iy < layout.chunksY(l); ++iy)
      for (int32_t ix = 0; ix < layout.chunksX(l); ++ix) {
        SCOPED_TRACE(std::to_string(l) + "/" + std::to_string(ix) + "/" + std::to_string(iy));
        const ChunkMesh mesh = mesher.build(l, ix, iy);
        const ChunkGeometry stored = roundTrip(mesh, budget, ChunkPayloadVersion::kStoredSkirts);
        const ChunkGeometry derived = roundTrip(mesh, budget, ChunkPayloadVersion::kDerivedSkirts);
        ASSERT_EQ(stored.parts.size(), 1u);
        ASSERT_EQ(derived.parts.size(), 1u);
        const ChunkPart &s = stored.parts[0], &d = derived.parts[0];
        // The same triangles in the same order, over the same vertices.
        ASSERT_EQ(d.surfaceIndexCount, s.surfaceIndexCount);
        ASSERT_EQ(test::rotatedTriangles(d), test::rotatedTriangles(s));
        ASSERT_EQ(d.vertices.size(), s.vertices.size());
        EXPECT_EQ(d.indices.size() - d.surfaceIndexCount, mesh.skirtIndices.size());
        skirted += d.indices.size() > d.surfaceIndexCount;
        std::map<std::pair<uint16_t, uint16_t>, int16_t> topDelta;
        for (size_t i = 0; i < s.vertices.size(); ++i) {
          const ChunkVertex &a = s.vertices[i], &b = d.vertices[i];
          ASSERT_EQ(a.x, b.x);
          ASSERT_EQ(a.y, b.y);
          const double za = worldZ(stored, a), zb = worldZ(derived, b);
          if (i < mesh.surfaceVertexCount) {  // the surface is the same
            ASSERT_EQ(a.morphDelta, b.morphDelta) << i;
            ASSERT_NEAR(zb, za, 1e-9) << i;
            topDelta[{b.x, b.y}] = b.morphDelta;
          } else {
            // A bottom: never shallower, at most a step deeper; it morphs exactly as its top
            // (version 1 rounded its target on its own, a step either way).
            ASSERT_LE(zb, za + 1e-9) << i;
            ASSERT_GE(zb, za - derived.zStep - 1e-9) << i;
            ASSERT_EQ(b.morphDelta, (topDelta.at({b.x, b.y}))) << i;
            ASSERT_LE(std::abs(a.morphDelta - b.morphDelta), 1) << i;
          }
        }
      }
  EXPECT_GT(skirted, 0u);
}

// 256-cell leaves at full density: 66,049 surface vertices, so the chunks are split into
// parts, and each part must leave room for the bottoms a reader derives for it.
TEST(DerivedSkirts, ChunksOfSeveralPartsLeaveRoomForTheirSkirts) {
  // Noise: every sample needs its vertex.
  Heightfield heights(513, 257);
  std::mt19937 rng(4);
  for (int32_t y = 0; y < 257; ++y)
    for (int32_t x = 0; x < 513; ++x) heights(x, y) = float(rng() % 1000) * 0.1f;
  const TreeLayout layout = makeTreeLayout(513, 257, 256).value();
  auto budget = makeErrorBudget(layout, 0.01, 100.0);
  ASSERT_TRUE(budget.ok()) << budget.error().message;
  MemoryHeights memory(heights);
  NullProgress progress;
  ActivationOptions options;
  options.blockCells = 256;
  const ActivationGrid grid =
      computeActivations(layout, *budget, memory, memory, options, progress).value();
  ChunkMesher mesher(layout, *budget, grid, memory);
  const ChunkMesh mesh = mesher.build(layout.depth, 0, 0);  // skirted on its east side
  ASSERT_GT(mesh.surfaceVertexCount, 65535u);
  ASSERT_GT(mesh.skirtIndices.size(), 0u);
  const ChunkGeometry derived = roundTrip(mesh, *budget, ChunkPayloadVersion::kDerivedSkirts);
  ASSERT_GT(derived.parts.size(), 1u);
  size_t skirtIndices = 0;
  for (const ChunkPart& part : derived.parts) {
    EXPECT_LE(part.vertices.size(), 65536u);
    skirtIndices += part.indices.size() - part.surfaceIndexCount;
  }
  EXPECT_EQ(skirtIndices, mesh.skirtIndices.size());
}

// Power-of-two and odd sizes (chunks clipped by the data's boundary, which has no skirts).
INSTANTIATE_TEST_SUITE_P(Terrains, DerivedSkirts,
                         ::testing::Values(std::tuple{65, 65, 1u}, std::tuple{97, 41, 2u},
                                           std::tuple{50, 70, 3u}));

}  // namespace
}  // namespace terralod
