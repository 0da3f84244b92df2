#include "terralod/tiles3d/tileset_json.h"

#include <gtest/gtest.h>

#include <vector>

namespace terralod::tiles3d {
namespace {

using nlohmann::json;

// A root chunk over 0..128 m with two of its children, and a grandchild.
std::vector<ExportTile> smallTree() {
  return {{kNoParent, 8.0, {0, 0, 90}, {128, 128, 130}, "tiles/0/0/0.glb"},
          {0, 4.0, {0, 0, 95}, {64, 64, 120}, "tiles/1/0/0.glb"},
          {0, 4.0, {64, 0, 92}, {128, 64, 128}, "tiles/1/1/0.glb"},
          {2, 2.0, {64, 0, 93}, {96, 32, 110}, "tiles/2/2/0.glb"}};
}

TEST(TilesetJson, TheChunkTreeAsExplicitTilesWithTheirErrorsAndBoxes) {
  glm::dmat4 frame(1.0);
  frame[3] = glm::dvec4(-2.1e6, -4.4e6, 3.9e6, 1.0);  // somewhere in Utah
  auto j = tilesetJson(smallTree(), frame, 16.0, {{"source", "ridge.tlod"}});
  ASSERT_TRUE(j.ok()) << j.error().message;
  EXPECT_EQ((*j)["asset"]["version"], "1.1");
  EXPECT_EQ((*j)["geometricError"], 16.0);
  EXPECT_EQ((*j)["extras"]["source"], "ridge.tlod");
  const json& root = (*j)["root"];
  // Column-major: the translation is entries 12..14.
  ASSERT_EQ(root["transform"].size(), 16u);
  EXPECT_EQ(root["transform"][12], -2.1e6);
  EXPECT_EQ(root["transform"][15], 1.0);
  EXPECT_EQ(root["geometricError"], 8.0);
  EXPECT_EQ(root["refine"], "REPLACE");
  EXPECT_EQ(root["content"]["uri"], "tiles/0/0/0.glb");
  EXPECT_EQ(root["boundingVolume"]["box"],
            json::array({64, 64, 110, 64, 0, 0, 0, 64, 0, 0, 0, 20}));
  ASSERT_EQ(root["children"].size(), 2u);
  EXPECT_EQ(root["children"][0]["content"]["uri"], "tiles/1/0/0.glb");
  EXPECT_FALSE(root["children"][0].contains("children"));
  const json& second = root["children"][1];
  ASSERT_EQ(second["children"].size(), 1u);
  EXPECT_EQ(second["children"][0]["geometricError"], 2.0);
  EXPECT_EQ(second["children"][0]["content"]["uri"], "tiles/2/2/0.glb");
  EXPECT_FALSE(second.contains("transform")) << "only the root is placed";
}

TEST(TilesetJson, SeveralRootsGetATileAboveThemWithoutContent) {
  std::vector<ExportTile> tiles = {{kNoParent, 8.0, {0, 0, 90}, {128, 128, 130}, "a.glb"},
                                   {kNoParent, 8.0, {128, 0, 80}, {256, 128, 100}, "b.glb"}};
  auto j = tilesetJson(tiles, glm::dmat4(1.0), 20.0);
  ASSERT_TRUE(j.ok());
  const json& root = (*j)["root"];
  EXPECT_FALSE(root.contains("content"));
  EXPECT_EQ(root["geometricError"], 20.0);
  EXPECT_EQ(root["boundingVolume"]["box"],
            json::array({128, 64, 105, 128, 0, 0, 0, 64, 0, 0, 0, 25}));
  EXPECT_EQ(root["children"].size(), 2u);
  EXPECT_FALSE(j->contains("extras"));
}

TEST(TilesetJson, RefusesTreesThatAreNotOne) {
  auto tiles = smallTree();
  tiles[3].geometricError = 5.0;
  EXPECT_EQ(tilesetJson(tiles, glm::dmat4(1.0), 16).error().message,
            "3D Tiles: tile 3's error exceeds its parent's");
  tiles = smallTree();
  tiles[1].parent = 2;
  EXPECT_EQ(tilesetJson(tiles, glm::dmat4(1.0), 16).error().message,
            "3D Tiles: tile 1 is listed before its parent");
  tiles = smallTree();
  tiles[2].min[2] = 200;
  EXPECT_EQ(tilesetJson(tiles, glm::dmat4(1.0), 16).error().message,
            "3D Tiles: tile 2 has an empty box");
  EXPECT_FALSE(tilesetJson({}, glm::dmat4(1.0), 16).ok());
}

}  // namespace
}  // namespace terralod::tiles3d
