#include "terralod/raster/void_fill.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

namespace terralod {
namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

// The method as docs/format.md states it, written the plain way: every level of the pyramid
// relaxed as a whole grid, sweep after sweep. fillVoids must give exactly these values.
struct Grid {
  int32_t w, h;
  std::vector<float> v;
  std::vector<uint8_t> ok;
  float at(int32_t x, int32_t y) const {
    return v[size_t(std::clamp(y, 0, h - 1)) * w + std::clamp(x, 0, w - 1)];
  }
};

std::vector<float> referenceFill(const Heightfield& heights) {
  std::vector<Grid> levels{
      {heights.columns(), heights.rows(), {heights.values().begin(), heights.values().end()}, {}}};
  for (float& value : levels[0].v) {
    levels[0].ok.push_back(std::isnan(value) ? 0 : 1);
    if (std::isnan(value)) value = 0.0f;
  }
  while (std::count(levels.back().ok.begin(), levels.back().ok.end(), 0) > 0) {
    const Grid& f = levels.back();
    Grid c{(f.w + 1) / 2, (f.h + 1) / 2, {}, {}};
    for (int32_t y = 0; y < c.h; ++y)
      for (int32_t x = 0; x < c.w; ++x) {
        double sum = 0;
        int n = 0;
        for (int32_t fy = 2 * y; fy < std::min(2 * y + 2, f.h); ++fy)
          for (int32_t fx = 2 * x; fx < std::min(2 * x + 2, f.w); ++fx)
            if (f.ok[size_t(fy) * f.w + fx]) sum += f.v[size_t(fy) * f.w + fx], ++n;
        c.v.push_back(n > 0 ? static_cast<float>(sum / n) : 0.0f);
        c.ok.push_back(n > 0 ? 1 : 0);
      }
    levels.push_back(std::move(c));
  }
  for (size_t k = levels.size() - 1; k-- > 0;) {
    Grid& f = levels[k];
    const Grid& c = levels[k + 1];
    for (int32_t y = 0; y < f.h; ++y)
      for (int32_t x = 0; x < f.w; ++x) {
        if (f.ok[size_t(y) * f.w + x]) continue;
        const double cx = (x - 0.5) * 0.5, cy = (y - 0.5) * 0.5;
        const int32_t x0 = int32_t(std::floor(cx)), y0 = int32_t(std::floor(cy));
        const double tx = cx - x0, ty = cy - y0;
        const double top = c.at(x0, y0) * (1 - tx) + c.at(x0 + 1, y0) * tx;
        const double bottom = c.at(x0, y0 + 1) * (1 - tx) + c.at(x0 + 1, y0 + 1) * tx;
        f.v[size_t(y) * f.w + x] = static_cast<float>(top * (1 - ty) + bottom * ty);
      }
    for (int sweep = 0; sweep < 8; ++sweep) {
      std::vector<float> next = f.v;
      for (int32_t y = 0; y < f.h; ++y)
        for (int32_t x = 0; x < f.w; ++x)
          if (!f.ok[size_t(y) * f.w + x])
            next[size_t(y) * f.w + x] =
                0.25f * (f.at(x - 1, y) + f.at(x + 1, y) + f.at(x, y - 1) + f.at(x, y + 1));
      f.v = std::move(next);
    }
  }
  return levels[0].v;
}

// Rolling terrain with `holes` random voids, some single samples and some square blobs.
Heightfield holey(int32_t w, int32_t h, int holes, uint32_t seed) {
  std::mt19937 rng(seed);
  Heightfield field(w, h);
  for (int32_t y = 0; y < h; ++y)
    for (int32_t x = 0; x < w; ++x)
      field.row(y)[x] = float(100 + 30 * std::sin(0.11 * x) * std::cos(0.07 * y) + 0.5 * x);
  for (int i = 0; i < holes; ++i) {
    const int32_t side = 1 + int32_t(rng() % 9);
    const int32_t x0 = int32_t(rng() % uint32_t(w)), y0 = int32_t(rng() % uint32_t(h));
    for (int32_t y = y0; y < std::min(h, y0 + side); ++y)
      for (int32_t x = x0; x < std::min(w, x0 + side); ++x) field.row(y)[x] = kNaN;
  }
  return field;
}

TEST(VoidFill, SameValuesAsWholeGridRelaxation) {
  struct Case {
    int32_t w, h;
    int holes;
  };
  const Case cases[] = {{64, 64, 3}, {97, 41, 40},   {1, 50, 5},
                        {33, 1, 4},  {128, 77, 400}, {20, 15, 0}};
  uint32_t seed = 1;
  for (const Case& c : cases) {
    Heightfield field = holey(c.w, c.h, c.holes, seed++);
    if (c.holes == 0) {  // the four corners and a whole edge
      for (int32_t x = 0; x < c.w; ++x) field.row(c.h - 1)[x] = kNaN;
      field.row(0)[0] = field.row(0)[c.w - 1] = kNaN;
    }
    const std::vector<float> expected = referenceFill(field);
    Result<uint64_t> filled = fillVoids(field, "holey.tif");
    ASSERT_TRUE(filled.ok()) << c.w << "x" << c.h;
    ASSERT_GT(*filled, 0u);
    for (size_t i = 0; i < expected.size(); ++i)
      ASSERT_EQ(field.values()[i], expected[i]) << c.w << "x" << c.h << " sample " << i;
  }
}

TEST(VoidFill, KeepsValidSamplesAndStaysWithinTheirRange) {
  Heightfield field = holey(150, 120, 120, 42);
  const Heightfield::Values before = field.values();
  float low = std::numeric_limits<float>::max(), high = -low;
  for (float v : before) {
    if (!std::isnan(v)) low = std::min(low, v), high = std::max(high, v);
  }
  Result<uint64_t> filled = fillVoids(field, "holey.tif");
  ASSERT_TRUE(filled.ok());
  EXPECT_EQ(*filled, uint64_t(std::count_if(before.begin(), before.end(),
                                            [](float v) { return std::isnan(v); })));
  for (size_t i = 0; i < before.size(); ++i) {
    const float v = field.values()[i];
    if (!std::isnan(before[i])) {
      ASSERT_EQ(v, before[i]) << i;
    }
    ASSERT_GE(v, low) << i;
    ASSERT_LE(v, high) << i;
  }
  EXPECT_EQ(countVoids(field), 0u);
}

TEST(VoidFill, ConstantSurroundingsFillConstant) {
  Heightfield field(40, 30);
  std::fill(field.values().begin(), field.values().end(), 250.0f);
  for (int32_t y = 5; y < 25; ++y)
    for (int32_t x = 3; x < 37; ++x) field.row(y)[x] = kNaN;
  ASSERT_TRUE(fillVoids(field, "flat.tif").ok());
  for (float v : field.values()) ASSERT_FLOAT_EQ(v, 250.0f);
}

TEST(VoidFill, NothingToFillAndNothingToFillFrom) {
  Heightfield full(8, 8);
  EXPECT_EQ(fillVoids(full, "full.tif").value(), 0u);
  Heightfield empty(8, 8);
  std::fill(empty.values().begin(), empty.values().end(), kNaN);
  const Result<uint64_t> r = fillVoids(empty, "empty.tif");
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("empty.tif"), std::string::npos) << r.error().message;
  EXPECT_NE(r.error().message.find("every sample is nodata"), std::string::npos);
}

// Sea left as nodata reaches the raster's edge and meets the coast near 0 m; voids in mountains
// that reach the edge, and voids inside the raster, are not sea.
TEST(VoidFill, SeaVoidsTouchTheEdgeAndMeetTheCoastNearSeaLevel) {
  Heightfield field(60, 40);
  for (int32_t y = 0; y < 40; ++y)
    for (int32_t x = 0; x < 60; ++x) field(x, y) = 5.0f + 40.0f * float(x - 8);  // coast at 5 m
  for (int32_t y = 0; y < 40; ++y)
    for (int32_t x = 0; x < 8; ++x) field(x, y) = kNaN;  // the sea, west
  for (int32_t y = 30; y < 40; ++y)
    for (int32_t x = 40; x < 45; ++x) field(x, y) = kNaN;  // a mountain void on the north edge
  for (int32_t y = 10; y < 14; ++y)
    for (int32_t x = 9; x < 12; ++x) field(x, y) = kNaN;  // a void inside, near the coast
  const SampleMask sea = seaVoids(field);
  EXPECT_EQ(sea.count(), 8u * 40u);
  for (int32_t y = 0; y < 40; ++y)
    for (int32_t x = 0; x < 60; ++x) ASSERT_EQ(sea.at(x, y), x < 8) << x << "," << y;
  EXPECT_TRUE(sea.at(-5, 3)) << "outside the grid, the nearest edge sample";
  EXPECT_FALSE(sea.at(70, 3));

  // A sea whose coast is mostly cliffs still counts when a quarter of it is low...
  Heightfield cliffs(20, 20, 200.0f);
  for (int32_t y = 0; y < 20; ++y) cliffs(0, y) = kNaN;
  for (int32_t y = 0; y < 5; ++y) cliffs(1, y) = 3.0f;
  EXPECT_EQ(seaVoids(cliffs).count(), 20u);
  // ... and not when less is.
  cliffs(1, 4) = 200.0f;
  EXPECT_EQ(seaVoids(cliffs).count(), 0u);
  // Without voids on the edge, nothing is stored.
  EXPECT_EQ(seaVoids(Heightfield(20, 20, 0.0f)).count(), 0u);
}

}  // namespace
}  // namespace terralod
