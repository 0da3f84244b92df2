// An edit rebuilds only the chunks its strokes reach (BuildOptions::reuse), and what it writes
// is the same bytes as building every chunk again.

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "temp_dir.h"
#include "terralod/build/builder.h"
#include "terralod/format/tileset_reader.h"

namespace terralod {
namespace {

using test::readWholeFile;
using test::TempDir;
using test::testData;

BuildSummary build(const BuildOptions& o) {
  NullProgress progress;
  auto s = buildTileset(o, progress, [](const std::string&) {});
  EXPECT_TRUE(s.ok()) << s.error().message;
  return s.ok() ? *s : BuildSummary{};
}

TEST(VipmEditReuse, KeptChunksGiveTheSameBytesAsBuildingEveryChunk) {
  TempDir dir;
  BuildOptions o;
  o.input = testData("crater_lake_0513.bt");
  o.kind = TilesetKind::kVipm;
  o.threads = 2;
  o.output = dir.file("before.tlod");
  build(o);
  // A stroke over a few chunks and one that moves nothing a root depends on, then paint.
  o.edits = {{Brush::kRaise, 5000.0, 7000.0, 300.0, 50.0, 0},
             {Brush::kSmooth, 2000.0, 3000.0, 900.0, 1.0, 0},
             {Brush::kPaint, 9000.0, 12000.0, 500.0, 0.0, 4}};
  o.output = dir.file("all.tlod");
  const BuildSummary all = build(o);
  EXPECT_EQ(all.reusedChunks, 0u);
  o.output = dir.file("kept.tlod");
  o.reuse = dir.file("before.tlod");
  const BuildSummary kept = build(o);
  EXPECT_GT(kept.reusedChunks, kept.chunks / 2);
  EXPECT_LT(kept.reusedChunks, kept.chunks);
  const auto a = TilesetReader::openFile(dir.file("all.tlod")).value();
  const auto k = TilesetReader::openFile(dir.file("kept.tlod")).value();
  EXPECT_EQ(a->header().levelError[0], k->header().levelError[0]);
  for (uint32_t i = 0; i < a->nodes().size(); ++i)
    EXPECT_TRUE(a->readNode(i).value().bytes == k->readNode(i).value().bytes) << "node " << i;
  EXPECT_TRUE(readWholeFile(dir.file("all.tlod")) == readWholeFile(dir.file("kept.tlod")));

  // An earlier build that is not a prefix of these edits is not used.
  o.output = dir.file("other.tlod");
  o.reuse = dir.file("kept.tlod");
  o.edits.erase(o.edits.begin());
  EXPECT_EQ(build(o).reusedChunks, 0u);
}

}  // namespace
}  // namespace terralod
