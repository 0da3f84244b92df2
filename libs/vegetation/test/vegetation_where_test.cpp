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
  EXPECT_TRUE(w->allows(1500, 10, "grass"));
  EXPECT_TRUE(w->allows(1500, 10, "meadow"));
  EXPECT_FALSE(w->allows(2400, 10, "grass"));  // strictly below
  EXPECT_FALSE(w->allows(50, 10, "grass"));
  EXPECT_FALSE(w->allows(1500, 35, "grass"));
  EXPECT_FALSE(w->allows(1500, 10, "rock"));
  auto any = parseVegetationWhere("slope>5");
  ASSERT_TRUE(any);
  EXPECT_TRUE(any->allows(9000, 6, "anything"));
  EXPECT_FALSE(any->allows(9000, 5, "anything"));
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
