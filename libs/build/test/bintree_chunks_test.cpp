// Chunk payload version 3 (rtin_chunk_codec.h): an RTIN chunk stored as its bintree decodes to
// exactly what payload version 2 stores for it (the same parts, vertices in the same order,
// the same triangles), on rasters whose edges clip the chunks' squares, and on chunks of
// several parts; and it is smaller.

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>

#include "chunk_triangles.h"
#include "terralod/build/activation_pass.h"
#include "terralod/build/chunk_encoder.h"
#include "terralod/build/chunk_mesher.h"
#include "terralod/format/rtin_chunk_codec.h"
#include "test_terrain.h"

namespace terralod {
namespace {

struct Totals {
  size_t chunks = 0, parts = 0, bintreeBytes = 0, meshoptBytes = 0;
};

// Every chunk of the raster both ways: the same geometry decoded.
void compareEveryChunk(const Heightfield& heights, int32_t leafCells, double maxError,
                       double heightRange, Totals& totals) {
  const TreeLayout layout = makeTreeLayout(heights.columns(), heights.rows(), leafCells).value();
  const ErrorBudget budget = makeErrorBudget(layout, maxError, heightRange).value();
  MemoryHeights memory(heights);
  NullProgress progress;
  ActivationOptions options;
  options.blockCells = std::max(leafCells, 32);
  const ActivationGrid grid =
      computeActivations(layout, budget, memory, memory, options, progress).value();
  ChunkMesher mesher(layout, budget, grid, memory);
  for (int32_t l = 0; l <= layout.depth; ++l)
    for (int32_t iy = 0; iy < layout.chunksY(l); ++iy)
      for (int32_t ix = 0; ix < layout.chunksX(l); ++ix) {
        if (!layout.chunkExists(l, ix, iy)) continue;
        SCOPED_TRACE(std::to_string(l) + "/" + std::to_string(ix) + "/" + std::to_string(iy));
        const ChunkMesh mesh = mesher.build(l, ix, iy);
        auto bintree = encodeChunkMesh(mesh, budget, ChunkPayloadVersion::kRtinCoded, 3);
        auto meshopt = encodeChunkMesh(mesh, budget, ChunkPayloadVersion::kDerivedSkirts, 3);
        if (!bintree.ok() || !meshopt.ok()) {
          ADD_FAILURE() << "chunk does not encode";
          return;
        }
        // Every RTIN chunk is stored as its bintree (none falls back to version 2).
        ASSERT_EQ(bintree->payload, ChunkPayloadVersion::kRtinCoded);
        auto a = decodeChunk(bintree->blob, "bintree");
        auto b = decodeChunk(meshopt->blob, "meshopt");
        ASSERT_TRUE(a.ok()) << a.error().message;
        ASSERT_TRUE(b.ok()) << b.error().message;
        EXPECT_EQ(a->zBase, b->zBase);
        EXPECT_EQ(a->zStep, b->zStep);
        EXPECT_EQ(a->skirtSteps, b->skirtSteps);
        ASSERT_EQ(a->parts.size(), b->parts.size());
        for (size_t p = 0; p < a->parts.size(); ++p) {
          const ChunkPart &pa = a->parts[p], &pb = b->parts[p];
          ASSERT_EQ(pa.vertices, pb.vertices) << "part " << p;
          ASSERT_EQ(pa.surfaceIndexCount, pb.surfaceIndexCount) << "part " << p;
          ASSERT_EQ(test::rotatedTriangles(pa), test::rotatedTriangles(pb)) << "part " << p;
        }
        ++totals.chunks;
        totals.parts += a->parts.size();
        totals.bintreeBytes += bintree->blob.size();
        totals.meshoptBytes += meshopt->blob.size();
      }
}

class BintreeChunks : public ::testing::TestWithParam<std::tuple<int, int, uint32_t>> {};

TEST_P(BintreeChunks, DecodeToWhatMeshoptStreamsStore) {
  const auto [columns, rows, seed] = GetParam();
  Totals totals;
  compareEveryChunk(test::makeTestTerrain(columns, rows, seed), 16, 0.5, 400.0, totals);
  if (HasFatalFailure()) return;
  EXPECT_GT(totals.chunks, 5u);
  EXPECT_LT(totals.bintreeBytes, totals.meshoptBytes);
}

// Square, clipped on one side, on both, and with the data ending mid-chunk at odd offsets.
INSTANTIATE_TEST_SUITE_P(Rasters, BintreeChunks,
                         ::testing::Values(std::tuple{129, 129, 1u}, std::tuple{129, 71, 2u},
                                           std::tuple{100, 77, 3u}, std::tuple{45, 130, 4u}));

// Noise at 256-cell leaves: every sample is a vertex, so chunks come in several parts, which
// the reader splits as the writer does.
TEST(BintreeChunks, SplitChunksOfSeveralPartsAsTheWriterDoes) {
  Heightfield heights(513, 257);
  std::mt19937 rng(4);
  for (int32_t y = 0; y < 257; ++y)
    for (int32_t x = 0; x < 513; ++x) heights(x, y) = float(rng() % 1000) * 0.1f;
  Totals totals;
  compareEveryChunk(heights, 256, 0.01, 100.0, totals);
  if (HasFatalFailure()) return;
  EXPECT_GT(totals.parts, totals.chunks);
}

// Squares over 512 cells number their vertices through a hash sized from the vertex count
// instead of the thread's dense table: a smooth terrain's coarse chunks (few vertices in a
// 1024-cell square), and noise whose 1024-cell root has every sample of a strip (over 160,000
// vertices, more than the hash is first sized for, so it grows while the walk goes).
TEST(BintreeChunks, LargeSquaresWithFewVertices) {
  Heightfield hills(1025, 1025);
  for (int32_t y = 0; y < 1025; ++y)
    for (int32_t x = 0; x < 1025; ++x)
      hills(x, y) = float(50.0 * std::sin(x / 90.0) * std::cos(y / 130.0));
  Totals smooth;
  compareEveryChunk(hills, 256, 0.5, 100.0, smooth);
  if (HasFatalFailure()) return;
  EXPECT_EQ(smooth.chunks, 21u);
}
TEST(BintreeChunks, LargeSquaresWithMoreVerticesThanTheHashFirstHolds) {
  // Noise in a strip along the south edge, flat beyond it.
  Heightfield noise(1025, 1025);
  std::mt19937 rng(6);
  for (int32_t y = 0; y < 1025; ++y)
    for (int32_t x = 0; x < 1025; ++x) noise(x, y) = y < 160 ? float(rng() % 1000) * 0.1f : 0.0f;
  Totals rough;
  compareEveryChunk(noise, 256, 0.01, 100.0, rough);
  if (HasFatalFailure()) return;
  EXPECT_EQ(rough.chunks, 21u);
  EXPECT_GT(rough.parts, rough.chunks);
}

}  // namespace
}  // namespace terralod
