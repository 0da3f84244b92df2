#include "terralod/build/builder.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>

#include "tamper_chunk.h"
#include "terralod/format/tileset_reader.h"
#include "terralod/format/tileset_writer.h"
#include "terralod/verify/verifier.h"
#include "test_terrain.h"

namespace terralod {
namespace {

namespace fs = std::filesystem;
using test::tamperChunk;

class TempDir {
 public:
  TempDir() {
    char name[] = "/tmp/terralod-build-test-XXXXXX";
    mPath = mkdtemp(name);
  }
  ~TempDir() { fs::remove_all(mPath); }
  std::string file(const std::string& name) const { return (mPath / name).string(); }

 private:
  fs::path mPath;
};

std::vector<uint8_t> fileBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

BuildSummary build(const std::string& input, const std::string& output, double maxError,
                   unsigned threads = 2, int32_t chunkCells = 0,
                   Streaming streaming = Streaming::kNever, int32_t blockCells = 512) {
  BuildOptions options;
  options.streaming = streaming;
  options.blockCells = blockCells;
  options.input = input;
  options.output = output;
  options.maxError = maxError;
  options.threads = threads;
  options.chunkCells = chunkCells;
  NullProgress progress;
  auto summary = buildTileset(options, progress, [](const std::string&) {});
  EXPECT_TRUE(summary.ok()) << (summary ? "" : summary.error().message);
  return summary ? *summary : BuildSummary{};
}

// The read-once tests' builds: `streaming`, 2 threads, streamed from 1,000 samples up (these
// rasters are small), the rest as `set` leaves the options.
BuildSummary buildStreamed(const std::string& input, const std::string& output, Streaming streaming,
                           const std::function<void(BuildOptions&)>& set) {
  BuildOptions options;
  options.input = input;
  options.output = output;
  options.streaming = streaming;
  options.streamAboveSamples = 1000;
  options.threads = 2;
  set(options);
  NullProgress progress;
  auto summary = buildTileset(options, progress, [](const std::string&) {});
  EXPECT_TRUE(summary.ok()) << (summary ? "" : summary.error().message);
  return summary ? *summary : BuildSummary{};
}

VerifyReport verify(const std::string& tileset, const std::string& source) {
  NullProgress progress;
  auto report = verifyTileset(tileset, source, {}, progress);
  EXPECT_TRUE(report.ok()) << (report ? "" : report.error().message);
  return report ? *report : VerifyReport{};
}

struct Case {
  int32_t columns, rows, chunkCells;
  double maxError;
  uint32_t seed;
  bool voids;
};

class BuildAndVerify : public ::testing::TestWithParam<Case> {};

// The conservative bound on randomized terrains: verify rasterises every decoded chunk over
// every source sample and finds no error above its level's bound, no crack, full coverage.
TEST_P(BuildAndVerify, BoundHoldsOnEverySample) {
  const Case c = GetParam();
  TempDir dir;
  Heightfield h = test::makeTestTerrain(c.columns, c.rows, c.seed);
  if (c.voids) {
    for (int32_t y = c.rows / 3; y < c.rows / 2; ++y)
      for (int32_t x = c.columns / 5; x < c.columns / 3; ++x) h(x, y) = std::nanf("");
    h(0, 0) = std::nanf("");
  }
  test::writeGeoTiff(h, dir.file("in.tif"), 2.5);
  const BuildSummary s =
      build(dir.file("in.tif"), dir.file("out.tlod"), c.maxError, 2, c.chunkCells);
  EXPECT_GT(s.triangles, 0u);
  if (c.voids) {
    EXPECT_GT(s.filledVoids, 0u);
  }
  const VerifyReport r = verify(dir.file("out.tlod"), dir.file("in.tif"));
  EXPECT_TRUE(r.ok()) << (r.failures.empty() ? "" : r.failures.front());
  ASSERT_EQ(r.levels.size(), size_t(s.levels));
  for (size_t l = 0; l < r.levels.size(); ++l) {
    EXPECT_LE(r.levels[l].maxError, r.levels[l].bound) << "level " << l;
    EXPECT_GT(r.levels[l].maxError, 0.2 * r.levels[l].bound)
        << "level " << l << " is needlessly fine";
    EXPECT_EQ(r.levels[l].uncovered, 0u);
  }
  EXPECT_GT(r.skirtPairs, 0u);
  EXPECT_GE(r.worstSkirtMargin, 0.0);
}

INSTANTIATE_TEST_SUITE_P(Terrains, BuildAndVerify,
                         ::testing::Values(Case{100, 37, 16, 1.0, 21, false},
                                           Case{257, 129, 32, 0.5, 22, false},
                                           Case{300, 300, 16, 2.0, 23, true},
                                           Case{65, 200, 8, 1.0, 24, true}));

// The streamed path (windows, sparse heights for the coarse levels) builds the same kind of
// tileset as the in-memory one: it verifies, and its meshes differ only through the height
// quantisation step, which it derives from an estimated height range.
TEST(Builder, StreamedBuildMatchesInMemory) {
  TempDir dir;
  test::writeGeoTiff(test::makeTestTerrain(301, 211, 31), dir.file("in.tif"), 5.0);
  const BuildSummary memory =
      build(dir.file("in.tif"), dir.file("memory.tlod"), 1.0, 2, 16, Streaming::kNever, 32);
  const BuildSummary streamed =
      build(dir.file("in.tif"), dir.file("streamed.tlod"), 1.0, 2, 16, Streaming::kAlways, 32);
  EXPECT_FALSE(memory.streamed);
  EXPECT_TRUE(streamed.streamed);
  EXPECT_EQ(streamed.chunks, memory.chunks);
  EXPECT_NEAR(double(streamed.triangles), double(memory.triangles),
              0.02 * double(memory.triangles));
  EXPECT_TRUE(verify(dir.file("streamed.tlod"), dir.file("in.tif")).ok());
  EXPECT_TRUE(verify(dir.file("memory.tlod"), dir.file("in.tif")).ok());
}

// Within the memory budget, an automatic streamed build decodes the raster once: pass 1 keeps
// only what pass 2 reads (KeptHeights: vertices, halos, leaf-chunk lines, the data's last row
// and column), and a textured build makes its textures in pass 1, from the windows pass 1
// reads with the texture margin (PassOneTextures). Either way the tileset is the one reading
// every window again gives. 301 x 211 with 16-cell leaves and 32-cell blocks: the data ends
// mid-block and mid-leaf on both axes.
TEST(Builder, StreamedBuildReadOnceIsTheSameTileset) {
  TempDir dir;
  test::writeGeoTiff(test::makeTestTerrain(301, 211, 33), dir.file("in.tif"), 5.0);
  auto buildWith = [&](Streaming streaming, uint64_t memoryMB, bool textures,
                       const std::string& name) {
    return buildStreamed(dir.file("in.tif"), dir.file(name), streaming, [&](BuildOptions& o) {
      o.memoryMB = memoryMB;
      o.blockCells = 32;
      o.chunkCells = 16;
      o.textures = textures;
      o.maxError = textures ? 1.0 : 0.25;
    });
  };
  for (const bool textures : {true, false}) {
    SCOPED_TRACE(textures ? "textured" : "untextured");
    const BuildSummary kept = buildWith(Streaming::kAuto, 64, textures, "kept.tlod");
    const BuildSummary windows = buildWith(Streaming::kAlways, 64, textures, "windows.tlod");
    EXPECT_TRUE(kept.streamed);
    EXPECT_TRUE(kept.readOnce);
    EXPECT_TRUE(windows.streamed);
    EXPECT_FALSE(windows.readOnce);
    EXPECT_EQ(fileBytes(dir.file("kept.tlod")), fileBytes(dir.file("windows.tlod")));
    EXPECT_GT(kept.keptSamples, 1000u);  // some samples, not all
    EXPECT_LT(kept.keptSamples, kept.sourceSamples);
    if (textures) {
      EXPECT_GT(kept.textureBytes, 0u);
    }
    // Over the budget nothing is kept.
    const BuildSummary over = buildWith(Streaming::kAuto, 0, textures, "over.tlod");
    EXPECT_TRUE(over.streamed);
    EXPECT_FALSE(over.readOnce);
    EXPECT_EQ(fileBytes(dir.file("over.tlod")), fileBytes(dir.file("windows.tlod")));
  }
}

// The textures made in pass 1 depend on the heights alone: when the estimated height range
// proves too small and pass 1 runs again with the true one, they are not made twice, and the
// tileset is still the one reading every window again gives. One sample far above the rest,
// on a row GDAL's approximate statistics skip (so the estimate does not see it), forces the
// second attempt; a block given to the texture pass twice is an internal error.
TEST(Builder, TexturesMadeInPassOneSurviveItsSecondAttempt) {
  TempDir dir;
  Heightfield h = test::makeTestTerrain(301, 211, 35);
  h(150, 113) += 3000.0f;
  test::writeGeoTiff(h, dir.file("in.tif"), 5.0);
  auto buildWith = [&](Streaming streaming, const std::string& name) {
    return buildStreamed(dir.file("in.tif"), dir.file(name), streaming, [](BuildOptions& o) {
      o.blockCells = 32;
      o.chunkCells = 16;
      o.maxError = 1.0;
    });
  };
  const BuildSummary once = buildWith(Streaming::kAuto, "once.tlod");
  const BuildSummary windows = buildWith(Streaming::kAlways, "windows.tlod");
  EXPECT_TRUE(once.readOnce);
  EXPECT_EQ(once.errorPasses, 2);
  EXPECT_EQ(windows.errorPasses, 2);
  EXPECT_GT(once.textureBytes, 0u);
  EXPECT_EQ(fileBytes(dir.file("once.tlod")), fileBytes(dir.file("windows.tlod")));
}

// Texture blocks held from pass 1 to pass 2 must fit the memory budget too: when they would
// not, the raster is kept whole (it fits) and pass 2 makes the textures, with the same bytes.
// 700 x 500 with a texture per chunk: 1.4 MB of heights, more than 2 MB of texture blocks.
TEST(Builder, TexturesTooLargeToHoldAreMadeInPassTwo) {
  TempDir dir;
  test::writeGeoTiff(test::makeTestTerrain(700, 500, 36), dir.file("in.tif"), 5.0);
  auto buildWith = [&](Streaming streaming, uint64_t memoryMB, const std::string& name) {
    return buildStreamed(dir.file("in.tif"), dir.file(name), streaming, [&](BuildOptions& o) {
      o.memoryMB = memoryMB;
      o.blockCells = 64;
      o.chunkCells = 16;
      o.textureSharing = TextureSharing::kEveryChunk;
    });
  };
  const BuildSummary tight = buildWith(Streaming::kAuto, 2, "tight.tlod");
  const BuildSummary roomy = buildWith(Streaming::kAuto, 64, "roomy.tlod");
  const BuildSummary windows = buildWith(Streaming::kAlways, 64, "windows.tlod");
  EXPECT_FALSE(windows.readOnce);
  EXPECT_TRUE(tight.readOnce);
  EXPECT_EQ(tight.keptSamples, 0u);  // every sample, in a Heightfield
  EXPECT_GT(roomy.keptSamples, 0u);  // textures in pass 1, KeptHeights
  EXPECT_EQ(fileBytes(dir.file("tight.tlod")), fileBytes(dir.file("windows.tlod")));
  EXPECT_EQ(fileBytes(dir.file("roomy.tlod")), fileBytes(dir.file("windows.tlod")));
}

// Untextured, what pass 1 keeps has a budget of its own: a raster larger than --memory-mb is
// still read once when the heights its meshes need fit.
TEST(Builder, UntexturedBuildKeepsWhatFitsTheBudget) {
  TempDir dir;
  test::writeGeoTiff(test::makeTestTerrain(700, 500, 34), dir.file("in.tif"), 5.0);  // 1.4 MB
  auto buildWith = [&](Streaming streaming, uint64_t memoryMB, const std::string& name) {
    return buildStreamed(dir.file("in.tif"), dir.file(name), streaming, [&](BuildOptions& o) {
      o.memoryMB = memoryMB;
      o.blockCells = 64;
      o.textures = false;
    });
  };
  const BuildSummary kept = buildWith(Streaming::kAuto, 1, "kept.tlod");
  const BuildSummary windows = buildWith(Streaming::kAlways, 1, "windows.tlod");
  EXPECT_TRUE(kept.streamed);  // 1.4 MB of heights over a 1 MB budget
  EXPECT_TRUE(kept.readOnce);
  EXPECT_GT(kept.keptSamples, 0u);
  EXPECT_LT(kept.keptSamples * sizeof(float), uint64_t{1} << 20);
  EXPECT_FALSE(windows.readOnce);
  EXPECT_EQ(fileBytes(dir.file("kept.tlod")), fileBytes(dir.file("windows.tlod")));
}

TEST(Builder, StreamedBuildFallsBackToMemoryForVoids) {
  TempDir dir;
  Heightfield h = test::makeTestTerrain(150, 150, 32);
  for (int32_t y = 60; y < 70; ++y)
    for (int32_t x = 20; x < 90; ++x) h(x, y) = std::nanf("");
  test::writeGeoTiff(h, dir.file("in.tif"));
  const BuildSummary s =
      build(dir.file("in.tif"), dir.file("out.tlod"), 1.0, 2, 16, Streaming::kAlways, 32);
  EXPECT_FALSE(s.streamed);
  EXPECT_EQ(s.filledVoids, 700u);
  EXPECT_TRUE(verify(dir.file("out.tlod"), dir.file("in.tif")).ok());
}

TEST(Builder, OutputDoesNotDependOnThreadCount) {
  TempDir dir;
  test::writeGeoTiff(test::makeTestTerrain(200, 150, 7), dir.file("in.tif"));
  for (Streaming streaming : {Streaming::kNever, Streaming::kAlways}) {
    build(dir.file("in.tif"), dir.file("one.tlod"), 1.0, 1, 0, streaming, 64);
    build(dir.file("in.tif"), dir.file("two.tlod"), 1.0, 2, 0, streaming, 64);
    const auto a = fileBytes(dir.file("one.tlod")), b = fileBytes(dir.file("two.tlod"));
    ASSERT_FALSE(a.empty());
    EXPECT_EQ(a, b);
  }
}

TEST(Verify, CatchesAChunkOutsideItsBound) {
  TempDir dir;
  test::writeGeoTiff(test::makeTestTerrain(129, 129, 8), dir.file("in.tif"));
  build(dir.file("in.tif"), dir.file("good.tlod"), 1.0);
  const uint32_t leaf =
      uint32_t(TilesetReader::openFile(dir.file("good.tlod")).value()->nodes().size() - 1);
  tamperChunk(dir.file("good.tlod"), dir.file("bad.tlod"), leaf, [](ChunkGeometry& g) {
    g.parts[0].vertices[g.parts[0].vertices.size() / 2].z += uint16_t(2.0 / g.zStep);
  });
  NullProgress progress;
  auto report = verifyTileset(dir.file("bad.tlod"), dir.file("in.tif"), {}, progress);
  ASSERT_TRUE(report.ok());
  EXPECT_FALSE(report->ok());
  auto reported = [&](const std::string& what) {
    return std::any_of(report->failures.begin(), report->failures.end(),
                       [&](const std::string& f) { return f.find(what) != std::string::npos; });
  };
  EXPECT_TRUE(reported("exceeds its level's bound")) << ::testing::PrintToString(report->failures);
  // The raised vertex also leaves the node's height bounds, which culling relies on.
  EXPECT_TRUE(reported("leave the node's bounds")) << ::testing::PrintToString(report->failures);
}

TEST(Verify, CatchesAMorphTargetOffItsParent) {
  TempDir dir;
  test::writeGeoTiff(test::makeTestTerrain(129, 129, 10), dir.file("in.tif"));
  build(dir.file("in.tif"), dir.file("good.tlod"), 1.0);
  NullProgress progress;
  auto good = verifyTileset(dir.file("good.tlod"), dir.file("in.tif"), {}, progress);
  ASSERT_TRUE(good.ok());
  ASSERT_TRUE(good->ok()) << ::testing::PrintToString(good->failures);
  ASSERT_GE(good->levels.size(), 2u);
  // Every level below the roots reports its allowance, (own step + parent's step) / 2 + slack,
  // and stays within it.
  for (size_t l = 1; l < good->levels.size(); ++l) {
    const LevelCheck& c = good->levels[l];
    EXPECT_DOUBLE_EQ(c.morphTolerance,
                     0.5 * (c.heightStep + good->levels[l - 1].heightStep) + kVerifySlack);
    EXPECT_LE(c.maxMorphMismatch, c.morphTolerance);
  }
  auto reader = TilesetReader::openFile(dir.file("good.tlod")).value();
  uint32_t victim = 0;
  while (reader->nodes()[victim].level != 1) ++victim;
  const double allowed = good->levels[1].morphTolerance;
  tamperChunk(dir.file("good.tlod"), dir.file("bad.tlod"), victim, [&](ChunkGeometry& g) {
    ChunkVertex& v = g.parts[0].vertices[g.parts[0].indices[0]];
    v.morphDelta = int16_t(v.morphDelta - int(std::ceil(2.0 * allowed / g.zStep)) - 1);
  });
  auto bad = verifyTileset(dir.file("bad.tlod"), dir.file("in.tif"), {}, progress);
  ASSERT_TRUE(bad.ok());
  EXPECT_FALSE(bad->ok());
  EXPECT_GT(bad->levels[1].maxMorphMismatch, bad->levels[1].morphTolerance);
  EXPECT_TRUE(std::any_of(bad->failures.begin(), bad->failures.end(), [](const std::string& f) {
    return f.find("fully morphed surface is") != std::string::npos;
  })) << ::testing::PrintToString(bad->failures);
}

TEST(Verify, CatchesAFullyMorphedChunkOffItsParentLevelsBound) {
  // While a chunk geomorphs it stands in for its parent: fully morphed, it must hold the
  // parent level's bound. One vertex of a level-1 chunk sent 2.5 x that bound below its target.
  TempDir dir;
  test::writeGeoTiff(test::makeTestTerrain(129, 129, 10), dir.file("in.tif"));
  build(dir.file("in.tif"), dir.file("good.tlod"), 1.0);
  auto reader = TilesetReader::openFile(dir.file("good.tlod")).value();
  uint32_t victim = 0;
  while (reader->nodes()[victim].level != 1) ++victim;
  const double parentBound = reader->header().levelError[0];
  tamperChunk(dir.file("good.tlod"), dir.file("bad.tlod"), victim, [&](ChunkGeometry& g) {
    ChunkVertex& v = g.parts[0].vertices[g.parts[0].indices[0]];
    v.morphDelta = int16_t(v.morphDelta - int(std::ceil(2.5 * parentBound / g.zStep)));
  });
  NullProgress progress;
  auto bad = verifyTileset(dir.file("bad.tlod"), dir.file("in.tif"), {}, progress);
  ASSERT_TRUE(bad.ok());
  EXPECT_FALSE(bad->ok());
  EXPECT_TRUE(std::any_of(bad->failures.begin(), bad->failures.end(), [](const std::string& f) {
    return f.find("fully morphed, error") != std::string::npos &&
           f.find("exceeds its parent level's bound") != std::string::npos;
  })) << ::testing::PrintToString(bad->failures);
}

TEST(Verify, CatchesMissingSkirts) {
  TempDir dir;
  test::writeGeoTiff(test::makeTestTerrain(129, 129, 9), dir.file("in.tif"));
  build(dir.file("in.tif"), dir.file("good.tlod"), 1.0);
  auto reader = TilesetReader::openFile(dir.file("good.tlod")).value();
  // Strip the skirts of every level-1 chunk: against level-2 neighbours something must crack.
  std::string current = dir.file("good.tlod");
  int stripped = 0;
  for (uint32_t i = 0; i < reader->nodes().size(); ++i) {
    if (reader->nodes()[i].level != 1) continue;
    const std::string next = dir.file("strip" + std::to_string(stripped++) + ".tlod");
    tamperChunk(current, next, i, [](ChunkGeometry& g) {
      for (ChunkPart& p : g.parts) p.indices.resize(p.surfaceIndexCount);
    });
    current = next;
  }
  NullProgress progress;
  auto report = verifyTileset(current, dir.file("in.tif"), {}, progress);
  ASSERT_TRUE(report.ok());
  EXPECT_FALSE(report->ok());
  bool crack = false;
  for (const std::string& f : report->failures) crack |= f.find("crack") != std::string::npos;
  EXPECT_TRUE(crack);
}

TEST(Builder, RefusesAnUnwritableOutputBeforeReadingAnything) {
  TempDir dir;
  test::writeGeoTiff(test::makeTestTerrain(65, 65, 1), dir.file("in.tif"));
  BuildOptions options;
  options.input = dir.file("in.tif");
  options.output = dir.file("missing/dir/out.tlod");
  NullProgress progress;
  auto summary = buildTileset(options, progress, [](const std::string&) {});
  ASSERT_FALSE(summary.ok());
  EXPECT_NE(summary.error().message.find("does not exist"), std::string::npos)
      << summary.error().message;
}

TEST(Builder, LeavesNoFileWhenTheInputIsAllVoid) {
  TempDir dir;
  Heightfield h(40, 30, std::nanf(""));
  test::writeGeoTiff(h, dir.file("void.tif"));
  BuildOptions options;
  options.input = dir.file("void.tif");
  options.output = dir.file("out.tlod");
  NullProgress progress;
  auto summary = buildTileset(options, progress, [](const std::string&) {});
  ASSERT_FALSE(summary.ok());
  EXPECT_NE(summary.error().message.find("nodata"), std::string::npos) << summary.error().message;
  EXPECT_EQ(std::distance(fs::directory_iterator(fs::path(dir.file("out.tlod")).parent_path()),
                          fs::directory_iterator{}),
            1);  // only the input is there: no tileset, no temporary
}

}  // namespace
}  // namespace terralod
