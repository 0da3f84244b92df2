#include "terralod/vegetation/vegetation_field.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>

namespace terralod::veg {
namespace {

// Heights from a function of (x, y) metres over [0, extent]², nothing outside.
class FunctionHeights final : public CornerHeights {
 public:
  FunctionHeights(float tileSize, double extent, std::function<float(double, double)> h)
      : mSize(tileSize), mExtent(extent), mHeight(std::move(h)) {}
  std::optional<std::array<float, 4>> tileCorners(uint32_t x, uint32_t y) override {
    const double x0 = x * double(mSize), y0 = y * double(mSize);
    const double x1 = x0 + mSize, y1 = y0 + mSize;
    if (x1 > mExtent || y1 > mExtent) return std::nullopt;
    return std::array<float, 4>{mHeight(x0, y0), mHeight(x1, y0), mHeight(x1, y1), mHeight(x0, y1)};
  }

 private:
  float mSize;
  double mExtent;
  std::function<float(double, double)> mHeight;
};

FieldLayout layout() {
  BakeSettings s;
  s.tileSize = 4;
  s.tileHeight = 2;
  s.seed = 7;
  s.resolutions = {468, 232, 151, 111, 88, 73, 62};
  return FieldLayout::over(s, 1000, 1000);
}

View viewFrom(glm::dvec3 eye, glm::dvec3 target) {
  Camera c;
  c.eye = eye;
  c.target = target;
  c.width = 800;
  c.height = 600;
  return makeView(c).value();
}

TEST(VegetationField, TilesInViewComeFarthestFirstEachWithTheResolutionItsSizeWants) {
  const FieldLayout l = layout();
  FunctionHeights flat(l.tileSize, 1000, [](double, double) { return 10.0f; });
  const View view = viewFrom({500, 300, 12}, {500, 400, 10});
  FieldStats stats;
  const std::vector<TileDraw> tiles = selectTiles(l, view, flat, {}, &stats);
  ASSERT_GT(tiles.size(), 50u);
  EXPECT_GT(stats.culled, 0u) << "tiles behind the eye are culled";
  const double range = ldiRange(l, view, {});
  for (size_t i = 0; i < tiles.size(); ++i) {
    const TileDraw& t = tiles[i];
    if (i > 0) {
      EXPECT_LE(t.distance, tiles[i - 1].distance);
    }
    EXPECT_LE(t.distance, range);
    EXPECT_EQ(t.prototile, l.tiling.at(t.x, t.y));
    // The coarsest resolution with at least as many pixels as the tile is wide on screen
    // times the oversampling.
    const double wide = t.screenPixels * FieldOptions{}.pixelsPerScreenPixel;
    if (t.resolution > 0) {
      EXPECT_GE(double(l.resolutions[size_t(t.resolution)]), wide);
    }
    if (t.resolution < kLdiResolutions - 1) {
      EXPECT_LT(double(l.resolutions[size_t(t.resolution) + 1]), wide);
    }
    EXPECT_EQ(t.placement.heights[0], 10.0f);
  }
  EXPECT_EQ(tiles.front().resolution, kLdiResolutions - 1);
  EXPECT_LT(tiles.back().resolution, 2);
}

TEST(VegetationField, TheDirectionIsTheLdiWhoseViewIsNearestTheLineOfSight) {
  const glm::dvec3 tile{100, 100, 0};
  EXPECT_EQ(directionFor({100, 50, 2}, tile), 0);   // from the south, looking north
  EXPECT_EQ(directionFor({50, 50, 2}, tile), 1);    // looking north-east
  EXPECT_EQ(directionFor({50, 100, 2}, tile), 2);   // looking east
  EXPECT_EQ(directionFor({100, 150, 2}, tile), 4);  // looking south
  EXPECT_EQ(directionFor({150, 100, 2}, tile), 6);  // looking west
  EXPECT_EQ(directionFor({104, 50, 2}, tile), 0);   // a few degrees off north
}

TEST(VegetationField, RulesLeaveOutTilesTooHighOrTooSteep) {
  const FieldLayout l = layout();
  // East of x = 500 the ground is 200 m up; north of y = 520 it rises at 45 degrees.
  FunctionHeights terrain(l.tileSize, 1000, [](double x, double y) {
    return float((x >= 500 ? 200.0 : 100.0) + std::max(0.0, y - 520));
  });
  const View view = viewFrom({500, 470, 150}, {500, 520, 100});
  auto count = [&](const char* rules, FieldStats* stats = nullptr) {
    FieldOptions o;
    o.rangeOversampling = 20;  // a wide range: many tiles on both sides
    if (rules) o.where = parseVegetationWhere(rules).value();
    return selectTiles(l, view, terrain, o, stats);
  };
  const auto all = count(nullptr);
  FieldStats stats;
  const auto low = count("height<150", &stats);
  ASSERT_GT(all.size(), low.size());
  EXPECT_GT(stats.excluded, 0u);
  for (const TileDraw& t : low) EXPECT_LT(t.placement.origin.x, 500.0f);
  const auto gentle = count("slope<30");
  ASSERT_GT(all.size(), gentle.size());
  for (const TileDraw& t : gentle) EXPECT_LE(t.placement.origin.y + l.tileSize, 520.0f);
}

TEST(VegetationField, NoTerrainNoTiles) {
  const FieldLayout l = layout();
  FunctionHeights small(l.tileSize, 40, [](double, double) { return 0.0f; });  // 10 × 10 tiles
  FieldStats stats;
  const auto tiles = selectTiles(l, viewFrom({20, -20, 5}, {20, 20, 0}), small, {}, &stats);
  EXPECT_GT(stats.noHeights, 0u);
  for (const TileDraw& t : tiles) {
    EXPECT_LT(t.x, 10u);
    EXPECT_LT(t.y, 10u);
  }
}

}  // namespace
}  // namespace terralod::veg
