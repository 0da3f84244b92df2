// Implicit quadtree tiling: Morton order, subtree files as the 3D Tiles 1.1 specification lays
// them out (header, JSON and binary chunks 8-byte aligned, availability bitstreams or
// constants), and the boxes implicit tiling derives for each tile.

#include "terralod/tiles3d/implicit_tiling.h"

#include <gtest/gtest.h>

#include <cstring>

namespace terralod::tiles3d {
namespace {

struct ParsedSubtree {
  nlohmann::json json;
  std::vector<uint8_t> binary;
};

ParsedSubtree parseSubtree(const std::vector<uint8_t>& bytes) {
  EXPECT_GE(bytes.size(), 24u);
  EXPECT_EQ(std::memcmp(bytes.data(), "subt", 4), 0);
  uint32_t version = 0;
  uint64_t jsonLength = 0, binaryLength = 0;
  std::memcpy(&version, bytes.data() + 4, 4);
  std::memcpy(&jsonLength, bytes.data() + 8, 8);
  std::memcpy(&binaryLength, bytes.data() + 16, 8);
  EXPECT_EQ(version, 1u);
  EXPECT_EQ(jsonLength % 8, 0u);
  EXPECT_EQ(binaryLength % 8, 0u);
  EXPECT_EQ(bytes.size(), 24 + jsonLength + binaryLength);
  ParsedSubtree p;
  p.json = nlohmann::json::parse(bytes.begin() + 24, bytes.begin() + 24 + long(jsonLength));
  p.binary.assign(bytes.begin() + 24 + long(jsonLength), bytes.end());
  return p;
}

// The bytes of an availability's bitstream.
std::vector<uint8_t> bitstream(const ParsedSubtree& p, const nlohmann::json& availability) {
  const auto& view = p.json["bufferViews"][availability["bitstream"].get<size_t>()];
  const size_t offset = view["byteOffset"], length = view["byteLength"];
  EXPECT_EQ(offset % 8, 0u);
  EXPECT_LE(offset + length, p.binary.size());
  return {p.binary.begin() + long(offset), p.binary.begin() + long(offset + length)};
}

TEST(ImplicitTiling, MortonIndexInterleavesXInTheLowerBits) {
  EXPECT_EQ(mortonIndex(0, 0), 0u);
  EXPECT_EQ(mortonIndex(1, 0), 1u);
  EXPECT_EQ(mortonIndex(0, 1), 2u);
  EXPECT_EQ(mortonIndex(1, 1), 3u);
  EXPECT_EQ(mortonIndex(2, 0), 4u);
  EXPECT_EQ(mortonIndex(3, 5), 0b100111u);
}

TEST(ImplicitTiling, SubtreesRecordWhichTilesAndChildSubtreesExist) {
  // Three levels in subtrees of two: the root and all of level 1, then level 2 under (1, 0, 0)
  // and (1, 1, 1) only.
  std::vector<TileKey> content = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {1, 0, 1}, {1, 1, 1}};
  for (uint32_t y = 0; y < 2; ++y)
    for (uint32_t x = 0; x < 2; ++x) {
      content.push_back({2, x, y});
      content.push_back({2, 2 + x, 2 + y});
    }
  auto files = subtreeFiles(content, 3, 2);
  ASSERT_TRUE(files.ok()) << files.error().message;
  ASSERT_EQ(files->size(), 9u);  // the root's, and one for each tile of level 2
  EXPECT_EQ((*files)[0].uri, "subtrees/0/0/0.subtree");
  const ParsedSubtree root = parseSubtree((*files)[0].bytes);
  EXPECT_EQ(root.json["tileAvailability"]["constant"], 1);
  EXPECT_EQ(root.json["contentAvailability"][0]["constant"], 1);
  // Level 2's tiles in Morton order: 0..3 under (1, 0, 0), 12..15 under (1, 1, 1).
  EXPECT_EQ(bitstream(root, root.json["childSubtreeAvailability"]),
            (std::vector<uint8_t>{0x0F, 0xF0}));
  EXPECT_EQ(root.json["childSubtreeAvailability"]["availableCount"], 8);
  EXPECT_EQ(root.json["buffers"][0]["byteLength"].get<size_t>(), root.binary.size());

  for (size_t i = 1; i < files->size(); ++i) {
    const SubtreeFile& f = (*files)[i];
    EXPECT_EQ(f.root.level, 2u);
    EXPECT_EQ(f.uri, "subtrees/2/" + std::to_string(f.root.x) + "/" + std::to_string(f.root.y) +
                         ".subtree");
    const ParsedSubtree p = parseSubtree(f.bytes);
    // Only the subtree's root (level 3 is beyond the tree); no subtrees below.
    EXPECT_EQ(bitstream(p, p.json["tileAvailability"]), (std::vector<uint8_t>{0x01}));
    EXPECT_EQ(p.json["tileAvailability"]["availableCount"], 1);
    EXPECT_EQ(bitstream(p, p.json["contentAvailability"][0]), (std::vector<uint8_t>{0x01}));
    EXPECT_EQ(p.json["childSubtreeAvailability"]["constant"], 0);
  }
}

TEST(ImplicitTiling, TilesAboveTheContentAreAvailableWithoutContent) {
  // Two roots side by side under a tile without content (a tileset of 2 x 1 roots).
  auto files = subtreeFiles(std::vector<TileKey>{{1, 0, 0}, {1, 1, 0}}, 2, 2);
  ASSERT_TRUE(files.ok());
  ASSERT_EQ(files->size(), 1u);
  const ParsedSubtree p = parseSubtree((*files)[0].bytes);
  EXPECT_EQ(bitstream(p, p.json["tileAvailability"]), (std::vector<uint8_t>{0b00111}));
  EXPECT_EQ(bitstream(p, p.json["contentAvailability"][0]), (std::vector<uint8_t>{0b00110}));
}

TEST(ImplicitTiling, RefusesTilesOutsideTheTreeOrListedTwice) {
  EXPECT_FALSE(subtreeFiles(std::vector<TileKey>{{1, 2, 0}}, 3, 2).ok());
  EXPECT_FALSE(subtreeFiles(std::vector<TileKey>{{3, 0, 0}}, 3, 2).ok());
  EXPECT_FALSE(subtreeFiles(std::vector<TileKey>{{1, 0, 0}, {1, 0, 0}}, 3, 2).ok());
}

TEST(ImplicitTiling, ATilesBoxIsItsQuarterOfItsParentsInXAndY) {
  const std::array<double, 12> root = {10, 20, 30, 100, 0, 0, 0, 50, 0, 0, 0, 5};
  const std::array<double, 12> box = implicitTileBox(root, {1, 1, 0});
  const std::array<double, 12> expected = {60, -5, 30, 50, 0, 0, 0, 25, 0, 0, 0, 5};
  for (size_t k = 0; k < 12; ++k) EXPECT_DOUBLE_EQ(box[k], expected[k]) << k;
  const std::array<double, 12> corner = implicitTileBox(root, {2, 3, 3});
  EXPECT_DOUBLE_EQ(corner[0], 10 + 75);
  EXPECT_DOUBLE_EQ(corner[1], 20 + 37.5);
  EXPECT_DOUBLE_EQ(corner[3], 25);
}

}  // namespace
}  // namespace terralod::tiles3d
