// Strokes applied to a VIPM chunk set rebuild only what they reach, and leave the set as a
// build of the edited source would be: same records, same bytes.

#include "terralod/build/vipm_chunk_set.h"

#include <gtest/gtest.h>

#include <algorithm>

#include <fstream>
#include <sstream>

#include "temp_dir.h"
#include "terralod/build/vipm_builder.h"
#include "terralod/materials/dem_classification.h"
#include "terralod/materials/terrain_edits.h"
#include "terralod/raster/dem_reader.h"
#include "terralod/vipm/vipm_blob.h"

namespace terralod {
namespace {

using test::readWholeFile;
struct Source {
  DemInfo info;
  Heightfield heights;
  MaterialMap materials;
};

Source read(const std::string& name) {
  auto reader = DemReader::open(test::testData(name), {}).value();
  Source s;
  s.info = reader->info();
  s.heights = Heightfield(s.info.columns, s.info.rows);
  EXPECT_TRUE(
      reader->readWindow(0, 0, s.info.columns, s.info.rows, s.heights.values().data()).ok());
  s.materials = classifyDem(*reader).value();
  return s;
}

BuildOptions options() {
  BuildOptions o;
  o.kind = TilesetKind::kVipm;
  o.threads = 2;
  o.vipmUpperLevels = kVipmUpperLevelsAuto;  // strokes remake the nodes above the roots too
  return o;
}

// A set built from `source` with the test options.
Result<VipmChunkSet> buildSet(const Source& source) {
  NullProgress progress;
  return VipmChunkSet::build(options(), source.info, source.heights, source.materials, 0, progress);
}

Source crater() {
  return read("crater_lake_0513.bt");
}
// 129 x 129 samples of 24 x 31 m: four leaves under one root.
Source small() {
  return read("gzcommon_dem_squared_129.tif");
}

TEST(VipmChunkSet, StrokesAppliedLaterGiveTheBuildOfTheEditedSource) {
  const Source source = crater();
  auto set = buildSet(source);
  ASSERT_TRUE(set.ok()) << set.error().message;
  const std::vector<NodeRecord> recordsBefore = set->nodes();
  std::vector<NodeBytes> bytesBefore;
  for (uint32_t i = 0; i < recordsBefore.size(); ++i) bytesBefore.push_back(set->nodeBytes(i));

  const std::vector<TerrainEdit> strokes = {{Brush::kRaise, 5000.0, 7000.0, 300.0, 50.0, 0},
                                            {Brush::kPaint, 9000.0, 12000.0, 500.0, 0.0, 4}};
  auto changed = set->apply(strokes, 2);
  ASSERT_TRUE(changed.ok()) << changed.error().message;
  EXPECT_EQ(set->edits(), strokes);
  EXPECT_GT(changed->size(), 4u);

  // The same strokes applied to the source before building.
  Source edited = source;
  applyHeightEdits(strokes, edited.info.spacingX, edited.info.spacingY, edited.heights);
  ASSERT_TRUE(applyPaintEdits(strokes, edited.info.spacingX, edited.info.spacingY, edited.materials,
                              "crater")
                  .ok());
  BuildOptions withStrokes = options();
  withStrokes.edits = strokes;
  NullProgress progress;
  auto fresh =
      VipmChunkSet::build(withStrokes, edited.info, edited.heights, edited.materials, 0, progress);
  ASSERT_TRUE(fresh.ok()) << fresh.error().message;
  EXPECT_EQ(fresh->levelErrors(), set->levelErrors());
  // Made again: the chunks the strokes reach and their ancestors, not the rest of the tree
  // (more records change: flange depths beside them).
  size_t remade = 0;
  for (uint32_t i = 0; i < recordsBefore.size(); ++i) {
    if (set->nodeBytes(i).bytes == bytesBefore[i].bytes) continue;
    ++remade;
    if (recordsBefore[i].level > 0) {
      const uint32_t parent = recordsBefore[i].parent;
      EXPECT_NE(set->nodeBytes(parent).bytes, bytesBefore[parent].bytes) << "node " << i;
    }
  }
  EXPECT_GT(remade, 4u);
  EXPECT_LT(remade, recordsBefore.size() / 4);
  for (uint32_t i = 0; i < recordsBefore.size(); ++i) {
    const NodeBytes now = set->nodeBytes(i);
    EXPECT_TRUE(now.bytes == fresh->nodeBytes(i).bytes) << "node " << i;
    EXPECT_EQ(set->nodes()[i].maxSkirtDepth, fresh->nodes()[i].maxSkirtDepth) << "node " << i;
    EXPECT_EQ(set->nodes()[i].maxZ, fresh->nodes()[i].maxZ) << "node " << i;
    // Every node whose bytes or record changed is listed.
    const bool listed = std::binary_search(changed->begin(), changed->end(), i);
    if (now.bytes != bytesBefore[i].bytes ||
        set->nodes()[i].maxSkirtDepth != recordsBefore[i].maxSkirtDepth) {
      EXPECT_TRUE(listed) << "node " << i << " changed but is not listed";
    }
  }
}

// An editor gets a stroke's leaves and roots first, then what changed above them: together
// every node a stroke changes, and the same set as applying it in one go.
TEST(VipmChunkSet, LeavesAndRootsAreHandedOverBeforeTheLevelsAboveThem) {
  const Source source = crater();
  auto once = buildSet(source);
  auto staged = buildSet(source);
  ASSERT_TRUE(once.ok() && staged.ok());
  const int32_t rootLevel = staged->layout().depth - 1;
  ASSERT_GT(rootLevel, 0);  // levels above the roots
  const std::vector<TerrainEdit> strokes = {{Brush::kRaise, 5000.0, 7000.0, 300.0, 50.0, 0}};
  auto all = once->apply(strokes, 2);
  ASSERT_TRUE(all.ok());

  std::vector<VipmInterimNode> near;
  std::vector<double> nearErrors;
  auto above = staged->apply(strokes, 2, {},
                             [&](std::vector<VipmInterimNode> nodes, const std::vector<double>& e) {
                               near = std::move(nodes);
                               nearErrors = e;
                             });
  ASSERT_TRUE(above.ok());
  ASSERT_FALSE(near.empty());
  ASSERT_FALSE(above->empty());
  std::vector<uint32_t> handed;
  for (const VipmInterimNode& n : near) {
    EXPECT_GE(int32_t(n.record.level), rootLevel) << "node " << n.node;
    handed.push_back(n.node);
  }
  EXPECT_TRUE(std::any_of(above->begin(), above->end(), [&](uint32_t i) {
    return int32_t(staged->nodes()[i].level) < rootLevel;
  }));
  // Handed over either way: every node the one-go apply changed.
  for (uint32_t i : *all)
    EXPECT_TRUE(std::find(handed.begin(), handed.end(), i) != handed.end() ||
                std::binary_search(above->begin(), above->end(), i))
        << "node " << i;
  // A leaf or root handed first and not again is final as handed.
  for (const VipmInterimNode& n : near)
    if (!std::binary_search(above->begin(), above->end(), n.node)) {
      EXPECT_TRUE(n.bytes.bytes == staged->nodeBytes(n.node).bytes) << "node " << n.node;
      EXPECT_EQ(n.record.maxSkirtDepth, staged->nodes()[n.node].maxSkirtDepth);
    }
  for (int32_t level = rootLevel; level <= staged->layout().depth; ++level)
    EXPECT_EQ(nearErrors[size_t(level)], staged->levelErrors()[size_t(level)]);
  for (uint32_t i = 0; i < once->nodes().size(); ++i) {
    EXPECT_TRUE(once->nodeBytes(i).bytes == staged->nodeBytes(i).bytes) << "node " << i;
    EXPECT_EQ(once->nodes()[i].maxSkirtDepth, staged->nodes()[i].maxSkirtDepth) << "node " << i;
  }
}

// What an editor writes back: the set after its strokes, as the tileset a build of the source
// with those strokes writes, byte for byte (strokes recorded).
TEST(VipmChunkSet, AnEditedSetIsWrittenAsTheBuildWithItsStrokes) {
  const Source source = small();
  auto set = buildSet(source);
  ASSERT_TRUE(set.ok());
  const std::vector<TerrainEdit> strokes = {{Brush::kLower, 2000.0, 2500.0, 400.0, 15.0, 0}};
  ASSERT_TRUE(set->apply(strokes, 2).ok());
  test::TempDir dir;
  ASSERT_TRUE(writeVipmTileset(*set, dir.file("written.tlod")).ok());
  BuildOptions o = options();
  o.input = source.info.path;
  o.output = dir.file("built.tlod");
  o.edits = strokes;
  NullProgress progress;
  ASSERT_TRUE(buildTileset(o, progress, [](const std::string&) {}).ok());
  EXPECT_TRUE(readWholeFile(dir.file("written.tlod")) == readWholeFile(dir.file("built.tlod")));
}

TEST(VipmChunkSet, AStrokeHandsItsChunksAsWholeGridsBeforeMakingThem) {
  // The interim an editor draws while the progressive meshes are made: every chunk the stroke
  // reaches, as its whole grid (no collapses) on the edited heights, with its old flange depth.
  const Source source = small();
  auto set = buildSet(source);
  ASSERT_TRUE(set.ok());
  const std::vector<NodeRecord> before = set->nodes();
  const std::vector<TerrainEdit> strokes = {{Brush::kRaise, 1000.0, 1000.0, 300.0, 40.0, 0}};
  Heightfield edited = source.heights;
  applyHeightEdits(strokes, source.info.spacingX, source.info.spacingY, edited);
  std::vector<VipmInterimNode> interim;
  auto changed = set->apply(
      strokes, 2, [&](std::vector<VipmInterimNode> nodes) { interim = std::move(nodes); });
  ASSERT_TRUE(changed.ok()) << changed.error().message;
  ASSERT_GE(interim.size(), 2u);  // a leaf and its root at least
  for (const VipmInterimNode& n : interim) {
    EXPECT_NE(std::find(changed->begin(), changed->end(), n.node), changed->end()) << n.node;
    const int32_t cells = n.node == 0 ? 128 : 64;
    const int32_t x0 = int32_t(n.record.x) * cells, y0 = int32_t(n.record.y) * cells;
    auto chunk =
        loadVipmChunk(std::span<const uint8_t>(n.bytes.bytes.data(), n.bytes.meshBytes), "interim");
    ASSERT_TRUE(chunk.ok()) << chunk.error().message;
    const int32_t w = chunk->data.width, h = chunk->data.height;
    EXPECT_EQ(w, std::min(cells, int32_t(source.info.columns) - 1 - x0) + 1);
    EXPECT_EQ(chunk->data.collapseCount(), 0u);
    EXPECT_EQ(chunk->data.vertexCount(), uint32_t(w * h));
    EXPECT_EQ(chunk->data.triangleCount(), uint32_t(2 * (w - 1) * (h - 1)));
    double worst = 0.0;
    for (const auto& p : chunk->unpacked.positions)
      worst = std::max(
          worst, std::abs(double(p[2]) - double(edited(x0 + int32_t(p[0]), y0 + int32_t(p[1])))));
    EXPECT_LE(worst, 0.5 * set->zStep() + 1e-3) << "node " << n.node;
    EXPECT_EQ(n.record.maxSkirtDepth, before[n.node].maxSkirtDepth);
    EXPECT_EQ(n.record.vertexCount, uint32_t(w * h));
    EXPECT_GT(n.bytes.bytes.size(), n.bytes.meshBytes);  // its normal map follows
  }
}

TEST(VipmChunkSet, ARefusedStrokeChangesNothing) {
  const Source source = small();
  auto set = buildSet(source);
  ASSERT_TRUE(set.ok());
  const NodeBytes before = set->nodeBytes(2);
  auto refused =
      set->apply(std::vector<TerrainEdit>{{Brush::kRaise, 1500.0, 2000.0, 300.0, 50.0, 0},
                                          {Brush::kPaint, 1500.0, 2000.0, 500.0, 0.0, 99}},
                 2);
  ASSERT_FALSE(refused.ok());
  EXPECT_NE(refused.error().message.find("paints material 99"), std::string::npos);
  // A raise that makes one root's relief too tall for 16-bit heights at a step of at most
  // --max-error (65,000 steps of 1 m).
  auto tooTall =
      set->apply(std::vector<TerrainEdit>{{Brush::kRaise, 1500.0, 2000.0, 300.0, 70000.0, 0}}, 2);
  ASSERT_FALSE(tooTall.ok());
  EXPECT_NE(tooTall.error().message.find("too fine for 16-bit heights"), std::string::npos);
  EXPECT_TRUE(set->edits().empty());
  EXPECT_TRUE(set->nodeBytes(2).bytes == before.bytes);
  // And the set still takes strokes afterwards, as if those had never been tried.
  auto ok = set->apply(std::vector<TerrainEdit>{{Brush::kLower, 1500.0, 2000.0, 300.0, 5.0, 0}}, 2);
  EXPECT_TRUE(ok.ok());
}

}  // namespace
}  // namespace terralod
