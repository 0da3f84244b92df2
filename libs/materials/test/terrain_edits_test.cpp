#include "terralod/materials/terrain_edits.h"

#include <gtest/gtest.h>

#include <cmath>

namespace terralod {
namespace {

// A tilted plane, spacing 2 x 3 m.
Heightfield plane(int32_t columns, int32_t rows) {
  Heightfield h(columns, rows);
  for (int32_t y = 0; y < rows; ++y)
    for (int32_t x = 0; x < columns; ++x) h(x, y) = float(100 + x + 2 * y);
  return h;
}

TEST(TerrainEdits, RaiseAddsTheAmountAtTheCentreFallingToNothingAtTheRadius) {
  const Heightfield before = plane(41, 31);
  Heightfield h = before;
  const TerrainEdit raise{Brush::kRaise, 40.0, 45.0, 20.0, 8.0, 0};  // grid point (20, 15)
  applyHeightEdits({raise}, 2.0, 3.0, h);
  EXPECT_FLOAT_EQ(h(20, 15), before(20, 15) + 8.0f);
  uint64_t changed = 0;
  for (int32_t y = 0; y < h.rows(); ++y)
    for (int32_t x = 0; x < h.columns(); ++x) {
      const double d = std::hypot(x * 2.0 - 40.0, y * 3.0 - 45.0);
      const double w = d < 20.0 ? std::pow(1.0 - d * d / 400.0, 2) : 0.0;
      EXPECT_NEAR(h(x, y), before(x, y) + 8.0 * w, 1e-4) << x << "," << y;
      changed += h(x, y) != before(x, y);
    }
  EXPECT_EQ(changed, touchedPoints(raise, 2.0, 3.0, 41, 31));
  EXPECT_GT(changed, 100u);
  // Lowering by the same amount undoes it (to float rounding).
  applyHeightEdits({{Brush::kLower, 40.0, 45.0, 20.0, 8.0, 0}}, 2.0, 3.0, h);
  for (size_t i = 0; i < h.values().size(); ++i)
    EXPECT_NEAR(h.values()[i], before.values()[i], 1e-4);
}

TEST(TerrainEdits, SmoothFlattensASpikeAndLeavesAPlaneAlone) {
  Heightfield h = plane(21, 21);
  const Heightfield flat = h;
  const TerrainEdit smooth{Brush::kSmooth, 20.0, 30.0, 15.0, 1.0, 0};  // point (10, 10)
  applyHeightEdits({smooth}, 2.0, 3.0, h);
  for (size_t i = 0; i < h.values().size(); ++i)  // the 3x3 mean of a plane is the plane
    EXPECT_NEAR(h.values()[i], flat.values()[i], 1e-3);
  h(10, 10) += 90.0f;
  applyHeightEdits({smooth}, 2.0, 3.0, h);
  EXPECT_NEAR(h(10, 10), flat(10, 10) + 10.0f, 1e-3);  // full strength at the centre: the mean
  EXPECT_NEAR(h(11, 10), flat(11, 10) + 10.0f * brushWeight(2.0, 15.0), 1e-3);
}

TEST(TerrainEdits, StrokesOverTheEdgeAreClippedAndStrokesOutsideTouchNothing) {
  Heightfield h = plane(11, 11);
  const TerrainEdit corner{Brush::kRaise, 0.0, 0.0, 5.0, 1.0, 0};
  EXPECT_EQ(touchedPoints(corner, 1.0, 1.0, 11, 11), 22u);  // x² + y² < 25, x, y >= 0
  const TerrainEdit outside{Brush::kRaise, -20.0, 5.0, 5.0, 1.0, 0};
  EXPECT_EQ(touchedPoints(outside, 1.0, 1.0, 11, 11), 0u);
  const TerrainEdit between{Brush::kRaise, 0.5, 0.5, 0.5, 1.0, 0};  // no point strictly within
  EXPECT_EQ(touchedPoints(between, 1.0, 1.0, 11, 11), 0u);
  const Heightfield before = h;
  applyHeightEdits({outside, between}, 1.0, 1.0, h);
  EXPECT_EQ(h.values(), before.values());
}

TEST(TerrainEdits, PaintSetsTheMaterialWithinTheRadiusAndRefusesUnknownIds) {
  MaterialMap m;
  m.columns = 9;
  m.rows = 9;
  m.classes.assign(81, 0);
  m.materials = {{3, "grass", {}}, {7, "rock", {}}};
  ASSERT_TRUE(applyPaintEdits({{Brush::kPaint, 4.0, 4.0, 2.0, 0.0, 7}}, 1.0, 1.0, m, "t").ok());
  for (int32_t y = 0; y < 9; ++y)
    for (int32_t x = 0; x < 9; ++x)
      EXPECT_EQ(m.at(x, y), std::hypot(x - 4.0, y - 4.0) < 2.0 ? 1 : 0) << x << "," << y;
  const Status bad = applyPaintEdits({{Brush::kPaint, 4.0, 4.0, 2.0, 0.0, 5}}, 1.0, 1.0, m, "t");
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.error().message,
            "t: edit 0 paints material 5, which the tileset does not have (3 grass, 7 rock)");
}

}  // namespace
}  // namespace terralod
