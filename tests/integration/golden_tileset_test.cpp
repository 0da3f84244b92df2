// The format is frozen: tilesets written by format versions 1 to 7 (static RTIN chunks,
// and VIPM chunks in version 2) must always read, and
// building their source again must give the same bytes (or scripts/update-golden-tileset.sh
// was run on purpose and the change reviewed).

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "chunk_triangles.h"
#include "cli_runner.h"
#include "terralod/format/tileset_reader.h"
#include "terralod/format/vipm_chunk_codec.h"
#include "terralod/vipm/vipm_levels.h"
#include "terralod/vipm/vipm_storage.h"

namespace terralod::test {
namespace {

// What the builder writes today: version 7 by default (RTIN chunks as their bintree, the shade
// layer); with --chunk-codec meshopt, version 4 without textures, version 6 with, version 5 with
// the generated colour baked.
const std::string kGoldenDefault = testData("golden/v7/gully.tlod");
const std::string kGolden = testData("golden/v4/gully-untextured.tlod");
const std::string kGoldenTextured = testData("golden/v6/gully.tlod");
const std::string kGoldenBaked = testData("golden/v5/gully.tlod");
const std::string kGoldenVipm = testData("golden/vipm/gully.tlod");

// golden/VERSION/NAME.tlod against its NAME.json.
void expectGoldenReads(const std::string& version, const std::string& name = "gully") {
  const auto expected =
      nlohmann::json::parse(readWholeFile(testData("golden/" + version + "/" + name + ".json")));
  auto opened = TilesetReader::openFile(testData("golden/" + version + "/" + name + ".tlod"));
  ASSERT_TRUE(opened.ok()) << opened.error().message;
  const TilesetReader& t = **opened;
  const bool textured = version != "v1" && name == "gully";
  EXPECT_EQ(t.header().version, uint32_t(version[1] - '0'));
  EXPECT_EQ(t.header().textured(), textured);
  EXPECT_EQ(t.header().levelCount, expected["levels"].get<uint32_t>());
  EXPECT_EQ(t.nodes().size(), expected["chunks"].get<size_t>());
  EXPECT_EQ(t.header().filledVoids, expected["filled_voids"].get<uint64_t>());
  for (uint32_t l = 0; l < t.header().levelCount; ++l)
    EXPECT_EQ(t.header().levelError[l], expected["level_error"][l].get<double>());
  for (int k = 0; k < 3; ++k) {
    EXPECT_EQ(t.header().extentMin[k], expected["extent"]["min"][k].get<double>());
    EXPECT_EQ(t.header().extentMax[k], expected["extent"]["max"][k].get<double>());
  }
  uint64_t triangles = 0, vertices = 0, withTexture = 0, inherited = 0;
  uint64_t skirtTriangles = 0, nodeSkirtTriangles = 0;  // decoded (or derived), and recorded
  for (uint32_t i = 0; i < t.nodes().size(); ++i) {
    auto chunk = t.readChunkData(i);
    ASSERT_TRUE(chunk.ok()) << chunk.error().message;
    for (const ChunkPart& p : chunk->geometry.parts) {
      triangles += p.surfaceIndexCount / 3;
      skirtTriangles += (p.indices.size() - p.surfaceIndexCount) / 3;
    }
    nodeSkirtTriangles += t.nodes()[i].skirtTriangleCount;
    vertices += t.nodes()[i].vertexCount;
    if (chunk->texture && chunk->texture->colourSource() &&
        chunk->texture->find(TextureLayerKind::kNormal))
      ++withTexture;
    // Version 5: a chunk may draw its parent's texture instead (its square of it).
    if (t.nodes()[i].inheritsTexture()) {
      ++inherited;
      const TextureSource source = textureSourceOf(t.nodes(), i);
      EXPECT_NE(source.owner, kNoNode);
      EXPECT_LT(source.owner, i);
    }
  }
  EXPECT_GT(skirtTriangles, 0u);
  EXPECT_EQ(skirtTriangles, nodeSkirtTriangles);
  EXPECT_EQ(triangles, expected["triangles"].get<uint64_t>());
  EXPECT_EQ(vertices, expected["vertices"].get<uint64_t>());
  EXPECT_EQ(withTexture + inherited, textured ? t.nodes().size() : 0u);
  EXPECT_EQ(inherited > 0, version >= "v5") << "versions 5 to 7 share textures (gully's do)";
  // Versions 6 and 7 store a shade layer where version 5 stores the colour.
  auto root = t.readChunkData(0);
  ASSERT_TRUE(root.ok()) << root.error().message;
  if (textured) {
    EXPECT_EQ(root->texture->colourSource()->kind,
              version >= "v6" ? TextureLayerKind::kShade : TextureLayerKind::kColor);
  }
}

// Builds gully again with `options` (after the golden's --max-error 0.25) and expects the
// bytes of `golden`.
void expectRebuildGives(const std::vector<std::string>& options, const std::string& golden) {
  TempDir dir;
  std::vector<std::string> args{"build",       testData("landlab_west_bijou_gully_3m.asc"),
                                "-o",          dir.file("again.tlod"),
                                "--max-error", "0.25",
                                "--threads",   "2"};
  args.insert(args.end(), options.begin(), options.end());
  const RunResult r = runTerralod(args);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_EQ(readWholeFile(dir.file("again.tlod")), readWholeFile(golden))
      << "the builder's output changed; if intended, run scripts/update-golden-tileset.sh";
}

TEST(GoldenTileset, VersionOneStillReads) {
  expectGoldenReads("v1");
}
TEST(GoldenTileset, VersionTwoStillReads) {
  expectGoldenReads("v2");
}
TEST(GoldenTileset, VersionThreeStillReads) {
  expectGoldenReads("v3");
}
TEST(GoldenTileset, VersionFourStillReads) {
  expectGoldenReads("v4");
  expectGoldenReads("v4", "gully-untextured");
}
TEST(GoldenTileset, VersionFiveReads) {
  expectGoldenReads("v5");
}
TEST(GoldenTileset, VersionSixReads) {
  expectGoldenReads("v6");
}

TEST(GoldenTileset, VersionSevenReads) {
  expectGoldenReads("v7");
}

// Version 7 stores the same chunks as version 6, in fewer bytes: every chunk decodes to the
// same parts, vertices and triangles (the meshopt index codec may rotate a triangle).
TEST(GoldenTileset, VersionSevenHoldsVersionSixsChunks) {
  auto seven = TilesetReader::openFile(kGoldenDefault);
  auto six = TilesetReader::openFile(kGoldenTextured);
  ASSERT_TRUE(seven.ok()) << seven.error().message;
  ASSERT_TRUE(six.ok()) << six.error().message;
  ASSERT_EQ((*seven)->nodes().size(), (*six)->nodes().size());
  uint64_t bytes7 = 0, bytes6 = 0;
  for (uint32_t i = 0; i < (*six)->nodes().size(); ++i) {
    auto a = (*seven)->readChunkData(i);
    auto b = (*six)->readChunkData(i);
    ASSERT_TRUE(a.ok()) << a.error().message;
    ASSERT_TRUE(b.ok()) << b.error().message;
    ASSERT_EQ(a->geometry.zBase, b->geometry.zBase) << i;
    ASSERT_EQ(a->geometry.parts.size(), b->geometry.parts.size()) << i;
    for (size_t p = 0; p < a->geometry.parts.size(); ++p) {
      ASSERT_EQ(a->geometry.parts[p].vertices, b->geometry.parts[p].vertices) << i;
      ASSERT_EQ(rotatedTriangles(a->geometry.parts[p]), rotatedTriangles(b->geometry.parts[p]))
          << i;
    }
    bytes7 += (*seven)->nodes()[i].blobBytes;
    bytes6 += (*six)->nodes()[i].blobBytes;
  }
  EXPECT_LT(bytes7, bytes6 * 3 / 4);
}

TEST(GoldenTileset, BuildingTheDefaultSourceAgainGivesTheSameBytes) {
  expectRebuildGives({}, kGoldenDefault);
}

TEST(GoldenTileset, BuildingTheSourceAgainGivesTheSameBytes) {
  expectRebuildGives({"--chunk-codec", "meshopt", "--no-texture"}, kGolden);
}

TEST(GoldenTileset, BuildingTheTexturedSourceAgainGivesTheSameBytes) {
  expectRebuildGives({"--chunk-codec", "meshopt"}, kGoldenTextured);
}

TEST(GoldenTileset, BuildingTheBakedColourAgainGivesTheSameBytes) {
  expectRebuildGives({"--chunk-codec", "meshopt", "--bake-colour"}, kGoldenBaked);
}

TEST(GoldenTileset, TheVipmTilesetStillReads) {
  const auto expected = nlohmann::json::parse(readWholeFile(testData("golden/vipm/gully.json")));
  auto opened = TilesetReader::openFile(kGoldenVipm);
  ASSERT_TRUE(opened.ok()) << opened.error().message;
  const TilesetReader& t = **opened;
  EXPECT_EQ(t.header().version, 2u);  // with its normal maps
  EXPECT_TRUE(t.header().textured());
  EXPECT_EQ(t.header().meshKind, MeshKind::kVipm);
  EXPECT_EQ(expected["kind"], "vipm");
  EXPECT_EQ(t.nodes().size(), expected["chunks"].get<size_t>());
  ASSERT_EQ(t.metadata().materials.size(), expected["materials"].size());
  for (size_t m = 0; m < t.metadata().materials.size(); ++m) {
    EXPECT_EQ(t.metadata().materials[m].name, expected["materials"][m]["name"]);
    EXPECT_EQ(colorHex(t.metadata().materials[m].color), expected["materials"][m]["color"]);
  }
  for (uint32_t l = 0; l < t.header().levelCount; ++l)
    EXPECT_EQ(t.header().levelError[l], expected["level_error"][l].get<double>());
  uint64_t triangles = 0, vertices = 0, collapses = 0;
  for (uint32_t i = 0; i < t.nodes().size(); ++i) {
    auto blob = t.readBlob(i);
    ASSERT_TRUE(blob.ok()) << blob.error().message;
    auto chunk = decodeVipmChunk(*blob, "golden chunk " + std::to_string(i));
    ASSERT_TRUE(chunk.ok()) << chunk.error().message;
    const UnpackedChunk unpacked = unpackChunk(*chunk);
    ASSERT_TRUE(VipmLevels::reconstruct(unpacked.mesh, unpacked.materials).ok());
    auto node = t.readNode(i);
    ASSERT_TRUE(node.ok()) << node.error().message;
    auto normals = decodeVipmNormalMap(
        node->texture(), uint32_t(t.header().chunkCells(t.nodes()[i].level)), "golden");
    ASSERT_TRUE(normals.ok()) << normals.error().message;
    triangles += chunk->triangleCount();
    vertices += chunk->vertexCount();
    collapses += chunk->collapseCount();
  }
  EXPECT_EQ(triangles, expected["triangles"].get<uint64_t>());
  EXPECT_EQ(vertices, expected["vertices"].get<uint64_t>());
  EXPECT_GT(collapses, 100u);  // leaves are progressive meshes, not single levels
}

TEST(GoldenTileset, BuildingTheVipmSourceAgainGivesTheSameBytes) {
  expectRebuildGives({"--kind", "vipm"}, kGoldenVipm);
}

}  // namespace
}  // namespace terralod::test
