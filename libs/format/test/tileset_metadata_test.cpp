#include "terralod/format/tileset_metadata.h"

#include <gtest/gtest.h>

namespace terralod {
namespace {

TilesetHeader threeLevels() {
  TilesetHeader h;
  h.levelCount = 3;
  return h;
}

std::string parseError(const std::string& json) {
  auto m = parseTilesetMetadata(json, threeLevels(), "m.tlod");
  return m.ok() ? "ok" : m.error().message;
}

TEST(TilesetMetadata, ReadsTheTypedFields) {
  const std::string json = R"({"generator": "terralod",
    "source": {"encoding": "terrarium", "band": 2, "nodata": -32768},
    "build": {"vertical_scale": 2.5, "max_error": 1},
    "texture": {"color": "generated", "levels": [
      {"color_size": 129, "normal_size": 65}, {"color_size": 257, "normal_size": 129},
      {"color_size": 257, "normal_size": 2}]}})";
  auto m = parseTilesetMetadata(json, threeLevels(), "m.tlod");
  ASSERT_TRUE(m.ok()) << m.error().message;
  EXPECT_EQ(m->sourceEncoding, "terrarium");
  EXPECT_EQ(m->sourceBand, 2);
  EXPECT_EQ(m->verticalScale, 2.5);
  const std::vector<TextureLevelSizes> levels{{129, 65}, {257, 129}, {257, 2}};
  EXPECT_EQ(m->textureLevels, levels);
  EXPECT_TRUE(m->sourceCrsWkt.empty());
  EXPECT_FALSE(m->sourceGeoTransform);
}

TEST(TilesetMetadata, ReadsTheSourcesGeoreferencing) {
  auto m = parseTilesetMetadata(
      R"({"source": {"crs_wkt": "PROJCRS[\"UTM 12N\"]",
                     "geotransform": [301905, 30, 0, 4154085, 0, -30]}})",
      threeLevels(), "m.tlod");
  ASSERT_TRUE(m.ok()) << m.error().message;
  EXPECT_EQ(m->sourceCrsWkt, "PROJCRS[\"UTM 12N\"]");
  EXPECT_EQ(m->sourceGeoTransform, (std::array<double, 6>{301905, 30, 0, 4154085, 0, -30}));
}

TEST(TilesetMetadata, AbsentFieldsTakeTheirDefaults) {
  auto m = parseTilesetMetadata("{}", threeLevels(), "m.tlod");
  ASSERT_TRUE(m.ok());
  EXPECT_EQ(m->sourceEncoding, "none");
  EXPECT_FALSE(m->sourceBand);
  EXPECT_EQ(m->verticalScale, 1.0);
  EXPECT_TRUE(m->textureLevels.empty());
  // A textured tileset written before the sizes were recorded: no levels, the renderer uses
  // GL's own mip sampling.
  EXPECT_EQ(parseError(R"({"texture": {"color": "generated"}})"), "ok");
}

TEST(TilesetMetadata, RefusesWhatIsNotWhatTheWriterWrites) {
  const std::string prefix = "m.tlod: invalid tileset metadata: ";
  EXPECT_EQ(parseError("not json"), prefix + "not a JSON object");
  EXPECT_EQ(parseError("[1, 2]"), prefix + "not a JSON object");
  EXPECT_EQ(parseError(R"({"source": 3})"), prefix + "\"source\" is not an object");
  EXPECT_EQ(parseError(R"({"source": {"encoding": 1}})"),
            prefix + "\"source\".\"encoding\" is not a string");
  EXPECT_EQ(parseError(R"({"source": {"band": 0}})"),
            prefix + "\"source\".\"band\" is not a band number");
  const std::string geo =
      prefix + "\"source\".\"geotransform\" is not six finite numbers with non-zero steps";
  EXPECT_EQ(parseError(R"({"source": {"geotransform": [0, 1, 0, 0, 0]}})"), geo);
  EXPECT_EQ(parseError(R"({"source": {"geotransform": [0, 0, 0, 0, 0, -1]}})"), geo);
  EXPECT_EQ(parseError(R"({"source": {"geotransform": [0, 1, 0, "x", 0, -1]}})"), geo);
  EXPECT_EQ(parseError(R"({"source": {"crs_wkt": 4326}})"),
            prefix + "\"source\".\"crs_wkt\" is not a string");
  EXPECT_EQ(parseError(R"({"build": {"vertical_scale": 0}})"),
            prefix + "\"build\".\"vertical_scale\" is not a non-zero number");
  EXPECT_EQ(parseError(R"({"texture": {"levels": [{"color_size": 3, "normal_size": 3}]}})"),
            prefix + "\"texture\".\"levels\" is not one entry per level (3)");
  const std::string bad = prefix + "texture level 1 has no valid \"";
  for (const char* level :
       {R"({"color_size": 128, "normal_size": 65})", R"({"color_size": 8193, "normal_size": 65})",
        R"({"color_size": -129, "normal_size": 65})", R"({"normal_size": 65})", R"(7)"})
    EXPECT_EQ(parseError(std::string(R"({"texture": {"levels": [)") +
                         R"({"color_size": 3, "normal_size": 3}, )" + level +
                         R"(, {"color_size": 3, "normal_size": 3}]}})"),
              bad + "color_size\" (2^k + 1 texels, at most 4097)")
        << level;
  EXPECT_EQ(parseError(R"({"texture": {"levels": [{"color_size": 3, "normal_size": 3},
              {"color_size": 3, "normal_size": 4}, {"color_size": 3, "normal_size": 3}]}})"),
            bad + "normal_size\" (2^k + 1 texels, at most 4097)");
}

// Version 6's shade layer: the snow line the shader interpolates over the rows.
TEST(TilesetMetadata, ReadsTheSnowLine) {
  auto m = parseTilesetMetadata(
      R"({"texture": {"color_layer": "shade", "snow_line": {"last_row": 1200,
          "metres": [2900.5, 2850, 2800]}}})",
      threeLevels(), "m.tlod");
  ASSERT_TRUE(m.ok()) << m.error().message;
  EXPECT_EQ(m->snowLineLastRow, 1200u);
  EXPECT_EQ(m->snowLine, (std::vector<float>{2900.5f, 2850, 2800}));
  const std::string prefix = "m.tlod: invalid tileset metadata: \"texture\".\"snow_line\" ";
  const std::string shape = prefix + "is not a last row and 2 to 1024 heights";
  EXPECT_EQ(parseError(R"({"texture": {"snow_line": [1, 2]}})"), shape);
  EXPECT_EQ(parseError(R"({"texture": {"snow_line": {"last_row": -1, "metres": [1, 2]}}})"), shape);
  EXPECT_EQ(parseError(R"({"texture": {"snow_line": {"last_row": 4294967296, "metres": [1, 2]}}})"),
            shape);
  EXPECT_EQ(parseError(R"({"texture": {"snow_line": {"last_row": 5, "metres": [1]}}})"), shape);
  EXPECT_EQ(parseError(R"({"texture": {"snow_line": {"last_row": 5, "metres": [1, "x"]}}})"),
            prefix + "has a height that is not a number of metres");
  EXPECT_EQ(parseError(R"({"texture": {"snow_line": {"last_row": 5, "metres": [1, 1e300]}}})"),
            prefix + "has a height that is not a number of metres");
}

TEST(TilesetMetadata, ReadsAVipmTilesetsMaterials) {
  TilesetHeader vipm;
  vipm.levelCount = 2;
  vipm.meshKind = MeshKind::kVipm;
  auto m = parseTilesetMetadata(
      R"({"build": {"materials": "classes.tif", "material_rules": false},
          "materials": [{"id": 11, "name": "water", "color": "#1f4e8C"},
                        {"id": 42, "name": "rock", "color": "#808080"}]})",
      vipm, "v.tlod");
  ASSERT_TRUE(m.ok()) << m.error().message;
  const std::vector<TilesetMaterial> expected{{11, "water", {0x1f, 0x4e, 0x8c}},
                                              {42, "rock", {0x80, 0x80, 0x80}}};
  EXPECT_EQ(m->materials, expected);
  EXPECT_EQ(m->materialsSource, "classes.tif");
  EXPECT_FALSE(m->materialRules);
  EXPECT_EQ(colorHex(expected[0].color), "#1f4e8c");

  const std::string prefix = "v.tlod: invalid tileset metadata: ";
  auto error = [&](const std::string& json) {
    auto r = parseTilesetMetadata(json, vipm, "v.tlod");
    return r.ok() ? "ok" : r.error().message;
  };
  EXPECT_EQ(error("{}"), prefix + "a VIPM tileset names no \"materials\"");
  EXPECT_EQ(error(R"({"materials": []})"), prefix + "a VIPM tileset names no \"materials\"");
  EXPECT_EQ(error(R"({"materials": 3})"),
            prefix + "\"materials\" is not an array of at most 8 materials");
  const std::string shape =
      prefix + "material 0 is not {\"id\": 0..255, \"name\": text, \"color\": \"#rrggbb\"}";
  for (const char* bad : {R"({"id": 256, "name": "a", "color": "#000000"})",
                          R"({"id": 1, "name": 2, "color": "#000000"})",
                          R"({"id": 1, "name": "a", "color": "#00000g"})",
                          R"({"id": 1, "name": "a", "color": "000000"})", R"(5)"})
    EXPECT_EQ(error(std::string(R"({"materials": [)") + bad + "]}"), shape) << bad;
  EXPECT_EQ(error(R"({"build": {"material_rules": 1}})"),
            prefix + "\"build\".\"material_rules\" is not true or false");
  // Static tilesets need none.
  EXPECT_EQ(parseError("{}"), "ok");
}

}  // namespace
}  // namespace terralod
