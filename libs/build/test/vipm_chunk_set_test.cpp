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
  return o;
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
  NullProgress progress;
  auto set =
      VipmChunkSet::build(options(), source.info, source.heights, source.materials, 0, progress);
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
  EXPECT_LT(changed->size(), recordsBefore.size() / 4);

  // The same strokes applied to the source before building.
  Source edited = source;
  applyHeightEdits(strokes, edited.info.spacingX, edited.info.spacingY, edited.heights);
  ASSERT_TRUE(applyPaintEdits(strokes, edited.info.spacingX, edited.info.spacingY, edited.materials,
                              "crater")
                  .ok());
  BuildOptions withStrokes = options();
  withStrokes.edits = strokes;
  auto fresh =
      VipmChunkSet::build(withStrokes, edited.info, edited.heights, edited.materials, 0, progress);
  ASSERT_TRUE(fresh.ok()) << fresh.error().message;
  EXPECT_EQ(fresh->rootLevelError(), set->rootLevelError());
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

// What an editor writes back: the set after its strokes, as the tileset a build of the source
// with those strokes writes, byte for byte (strokes recorded).
TEST(VipmChunkSet, AnEditedSetIsWrittenAsTheBuildWithItsStrokes) {
  const Source source = small();
  NullProgress progress;
  auto set =
      VipmChunkSet::build(options(), source.info, source.heights, source.materials, 0, progress);
  ASSERT_TRUE(set.ok());
  const std::vector<TerrainEdit> strokes = {{Brush::kLower, 2000.0, 2500.0, 400.0, 15.0, 0}};
  ASSERT_TRUE(set->apply(strokes, 2).ok());
  test::TempDir dir;
  ASSERT_TRUE(writeVipmTileset(*set, dir.file("written.tlod")).ok());
  BuildOptions o = options();
  o.input = source.info.path;
  o.output = dir.file("built.tlod");
  o.edits = strokes;
  ASSERT_TRUE(buildTileset(o, progress, [](const std::string&) {}).ok());
  EXPECT_TRUE(readWholeFile(dir.file("written.tlod")) == readWholeFile(dir.file("built.tlod")));
}

TEST(VipmChunkSet, ARefusedStrokeChangesNothing) {
  const Source source = small();
  NullProgress progress;
  auto set =
      VipmChunkSet::build(options(), source.info, source.heights, source.materials, 0, progress);
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
