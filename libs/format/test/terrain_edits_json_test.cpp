#include "terralod/format/terrain_edits_json.h"

#include <gtest/gtest.h>

namespace terralod {
namespace {

TEST(TerrainEditsJson, AScriptReadsBackWhatItWrote) {
  const std::vector<TerrainEdit> edits = {
      {Brush::kRaise, 1500.25, 2000.0 / 3.0, 400.0, 80.125, 0},
      {Brush::kLower, -10.0, 1e7, 0.1, 1e-3, 0},
      {Brush::kSmooth, 0.0, 0.0, 30.0, 0.5, 0},
      {Brush::kPaint, 12.0, 13.0, 14.0, 0.0, 4},
  };
  auto back = parseTerrainEditScript(terrainEditScript(edits), "e.json");
  ASSERT_TRUE(back.ok()) << back.error().message;
  EXPECT_EQ(*back, edits);
}

TEST(TerrainEditsJson, TheIssuesExampleParses) {
  auto edits = parseTerrainEditScript(
      R"({"edits": [{"brush": "raise", "center": [10, 20], "radius": 5, "amount": 2},
                    {"brush": "paint", "center": [1, 2], "radius": 3, "amount": 1, "material": 7}]})",
      "e.json");
  ASSERT_TRUE(edits.ok()) << edits.error().message;
  ASSERT_EQ(edits->size(), 2u);
  EXPECT_EQ((*edits)[0].brush, Brush::kRaise);
  EXPECT_EQ((*edits)[0].centerY, 20.0);
  EXPECT_EQ((*edits)[0].amount, 2.0);
  EXPECT_EQ((*edits)[1].brush, Brush::kPaint);
  EXPECT_EQ((*edits)[1].material, 7);
}

// Every mistake is one line naming the file, the entry and the field.
TEST(TerrainEditsJson, MistakesAreOneLineNamingTheEntry) {
  const std::string ok = R"("center": [1, 2], "radius": 3)";
  const std::pair<std::string, std::string> cases[] = {
      {"{", "e.json: is not valid JSON"},
      {"[]", "e.json: is not {\"edits\": [...]}"},
      {R"({"edits": 3})", "e.json: edits is not an array"},
      {R"({"edits": [3]})", "e.json: edits[0]: is not an object"},
      {R"({"edits": [{"brush": "dig", )" + ok + R"(, "amount": 1}]})",
       "e.json: edits[0]: \"brush\" is not one of"},
      {R"({"edits": [{"brush": "raise", "center": [1], "radius": 3, "amount": 1}]})",
       "e.json: edits[0]: \"center\" is not [x, y]"},
      {R"({"edits": [{"brush": "raise", "center": [1, 2], "radius": 0, "amount": 1}]})",
       "e.json: edits[0]: \"radius\" is not a number of metres greater than 0"},
      {R"({"edits": [{"brush": "raise", )" + ok + "}]}",
       "e.json: edits[0]: \"amount\" is not a number of metres"},
      {R"({"edits": [{"brush": "lower", )" + ok + R"(, "amount": -1}]})",
       "e.json: edits[0]: \"amount\" is not a number of metres"},
      {R"({"edits": [{"brush": "smooth", )" + ok + R"(, "amount": 1.5}]})",
       "e.json: edits[0]: \"amount\" is not a strength in (0, 1]"},
      {R"({"edits": [{"brush": "raise", )" + ok + R"(, "amount": 1}, {"brush": "paint", )" + ok +
           "}]}",
       "e.json: edits[1]: a paint edit's \"material\" is not a material id 0..255"},
      {R"({"edits": [{"brush": "raise", )" + ok + R"(, "amount": 1, "material": 2}]})",
       "e.json: edits[0]: \"material\" belongs to paint edits, not raise"},
      {R"({"edits": [{"brush": "raise", )" + ok + R"(, "amount": 1, "radious": 2}]})",
       "e.json: edits[0]: unknown field \"radious\""},
  };
  for (const auto& [text, expected] : cases) {
    auto parsed = parseTerrainEditScript(text, "e.json");
    ASSERT_FALSE(parsed.ok()) << text;
    EXPECT_EQ(parsed.error().message.rfind(expected, 0), 0u)
        << text << "\n  got: " << parsed.error().message;
    EXPECT_EQ(parsed.error().message.find('\n'), std::string::npos);
  }
}

}  // namespace
}  // namespace terralod
