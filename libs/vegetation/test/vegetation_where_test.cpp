#include "terralod/vegetation/vegetation_where.h"

#include <gtest/gtest.h>

namespace terralod::veg {
namespace {

TEST(VegetationWhere, AConjunctionOfHeightSlopeAndMaterials) {
  auto w = parseVegetationWhere("height<2400,slope<30,material=grass|meadow,height>100");
  ASSERT_TRUE(w) << w.error().message;
  EXPECT_EQ(*w->heightBelow, 2400);
  EXPECT_EQ(*w->heightAbove, 100);
  EXPECT_EQ(*w->slopeBelow, 30);
  EXPECT_FALSE(w->slopeAbove);
  EXPECT_EQ(w->materials, (std::vector<std::string>{"grass", "meadow"}));
  // Materials on a 3 x 2 grid 10 m apart: rock, grass, meadow / grass, rock, rock.
  MaterialMap map{3, 2, {0, 1, 2, 1, 0, 0}, {{1, "rock", {}}, {2, "grass", {}}, {3, "meadow", {}}}};
  EXPECT_FALSE(w->allows(1500, 10, {10, 0})) << "an unresolved material rule allows nothing";
  auto mask = MaterialMask::from(map, 10, 10, w->materials, "classes.tif");
  ASSERT_TRUE(mask) << mask.error().message;
  w->materialMask = std::make_shared<const MaterialMask>(std::move(mask).value());
  EXPECT_TRUE(w->allows(1500, 10, {10, 0}));    // grass
  EXPECT_TRUE(w->allows(1500, 10, {21, 4}));    // nearest point: meadow
  EXPECT_TRUE(w->allows(1500, 10, {-50, 11}));  // clamped: grass
  EXPECT_FALSE(w->allows(1500, 10, {14, 6}));   // nearest point: rock
  EXPECT_FALSE(w->allows(2400, 10, {10, 0}));   // strictly below
  EXPECT_FALSE(w->allows(50, 10, {10, 0}));
  EXPECT_FALSE(w->allows(1500, 35, {10, 0}));
  EXPECT_FALSE(w->allows(1500, 10, {0, 0}));  // rock
  auto any = parseVegetationWhere("slope>5");
  ASSERT_TRUE(any);
  EXPECT_TRUE(any->allows(9000, 6, {}));
  EXPECT_FALSE(any->allows(9000, 5, {}));
}

TEST(VegetationWhere, MaterialNamesAreCheckedAgainstTheTerrains) {
  MaterialMap map{2, 1, {0, 1}, {{1, "rock", {}}, {2, "grass", {}}}};
  auto mask = MaterialMask::from(map, 1, 1, {"grass", "snow"}, "zion.tlod");
  ASSERT_FALSE(mask);
  EXPECT_EQ(mask.error().message,
            "--vegetation-where: material 'snow' is not one of: rock, grass (in zion.tlod)");
}

TEST(VegetationWhere, LargeMaterialGridsAreSubsampledToTheMasksSide) {
  const int32_t side = 2 * kMaxMaterialMaskSide + 1;
  MaterialMap map{
      side, 1, std::vector<uint8_t>(size_t(side), 0), {{1, "rock", {}}, {2, "grass", {}}}};
  map.classes[21] = 1;  // the mask's point 7 (every third point)
  auto mask = MaterialMask::from(map, 2, 2, {"grass"}, "big.tif");
  ASSERT_TRUE(mask);
  EXPECT_EQ(mask->columns, (side + 2) / 3);
  EXPECT_EQ(mask->cellX, 6);
  EXPECT_TRUE(mask->allowsAt(42, 0));   // 21 points of 2 m
  EXPECT_TRUE(mask->allowsAt(44, 0));   // nearest mask point: 7
  EXPECT_FALSE(mask->allowsAt(46, 0));  // nearest: 8
  EXPECT_FALSE(mask->allowsAt(38, 0));  // nearest: 6
}

TEST(VegetationWhere, BadTermsGetOneLineNamingTheTerm) {
  for (const auto& [text, says] : std::vector<std::pair<std::string, std::string>>{
           {"", "empty"},
           {"height", "'height': expected"},
           {"height<abc", "'height<abc': not a number"},
           {"height<1e999", "not a number"},
           {"height=3", "take < or >"},
           {"slope<95", "0 to 90"},
           {"width<3", "unknown quantity 'width'"},
           {"material<grass", "named with ="},
           {"material=grass|", "empty material"},
           {"material=a,material=b", "given twice"},
           {"height<1,height<2", "given twice"},
           {"height<1,", "''"},
       }) {
    auto w = parseVegetationWhere(text);
    ASSERT_FALSE(w) << text;
    EXPECT_EQ(w.error().message.rfind("--vegetation-where: ", 0), 0u) << w.error().message;
    EXPECT_NE(w.error().message.find(says), std::string::npos) << text << ": " << w.error().message;
    EXPECT_EQ(w.error().message.find('\n'), std::string::npos);
  }
}

}  // namespace
}  // namespace terralod::veg
