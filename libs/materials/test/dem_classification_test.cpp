#include "terralod/materials/dem_classification.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <vector>

#include "temp_dir.h"

namespace terralod {
namespace {

std::unique_ptr<DemReader> openDem(const std::string& name) {
  auto dem = DemReader::open(test::testData(name), {});
  EXPECT_TRUE(dem.ok()) << (dem.ok() ? "" : dem.error().message);
  return dem.ok() ? std::move(dem).value() : nullptr;
}

// Slope in degrees at every grid point, written the plain way from the whole DEM: central
// differences, one-sided at the edges and next to voids.
struct Slopes {
  std::vector<float> heights;
  std::vector<double> degrees;
  double lo = INFINITY, hi = -INFINITY;
};

Slopes computeSlopes(const DemReader& dem) {
  const DemInfo& info = dem.info();
  const int32_t w = info.columns, h = info.rows;
  Slopes s;
  s.heights.resize(size_t(w) * h);
  EXPECT_TRUE(dem.readWindow(0, 0, w, h, s.heights.data()).ok());
  auto at = [&](int32_t x, int32_t y) { return s.heights[size_t(y) * w + x]; };
  s.degrees.assign(s.heights.size(), 0.0);
  for (int32_t y = 0; y < h; ++y)
    for (int32_t x = 0; x < w; ++x) {
      const float c = at(x, y);
      if (std::isnan(c)) continue;
      s.lo = std::min(s.lo, double(c));
      s.hi = std::max(s.hi, double(c));
      auto diff = [&](int32_t ax, int32_t ay, int32_t bx, int32_t by, double spacing) {
        const bool aOk = ax >= 0 && ay >= 0 && !std::isnan(at(ax, ay));
        const bool bOk = bx < w && by < h && !std::isnan(at(bx, by));
        const double a = aOk ? at(ax, ay) : c, b = bOk ? at(bx, by) : c;
        const int steps = int(aOk) + int(bOk);
        return steps ? (b - a) / (steps * spacing) : 0.0;
      };
      const double gx = diff(x - 1, y, x + 1, y, info.spacingX);
      const double gy = diff(x, y - 1, x, y + 1, info.spacingY);
      s.degrees[size_t(y) * w + x] = std::atan(std::hypot(gx, gy)) * 180 / std::numbers::pi;
    }
  return s;
}

void checkAgainstSlopes(const std::string& name) {
  auto dem = openDem(name);
  ASSERT_TRUE(dem);
  const auto start = std::chrono::steady_clock::now();
  auto map = classifyDem(*dem);
  const double ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  std::printf("classifyDem(%s): %.1f ms\n", name.c_str(), ms);
  ASSERT_TRUE(map.ok()) << map.error().message;
  ASSERT_EQ(map->columns, dem->info().columns);
  ASSERT_EQ(map->rows, dem->info().rows);
  ASSERT_EQ(map->classes.size(), size_t(map->columns) * map->rows);
  ASSERT_EQ(map->materials.size(), 5u);
  const char* names[] = {"water", "grass", "soil", "rock", "snow"};
  for (size_t i = 0; i < 5; ++i) {
    EXPECT_EQ(map->materials[i].id, i);
    EXPECT_EQ(map->materials[i].name, names[i]);
  }

  const Slopes s = computeSlopes(*dem);
  std::vector<size_t> counts(5, 0);
  for (int32_t y = 0; y < map->rows; ++y)
    for (int32_t x = 0; x < map->columns; ++x) {
      const uint8_t m = map->at(x, y);
      ASSERT_LT(m, 5) << x << "," << y;
      ++counts[m];
      const size_t i = size_t(y) * map->columns + x;
      const float hgt = s.heights[i];
      if (std::isnan(hgt)) {
        EXPECT_EQ(m, kWater) << "void at " << x << "," << y;
        continue;
      }
      const double slope = s.degrees[i], t = (hgt - s.lo) / (s.hi - s.lo);
      // Margins of 0.01 degree: the library compares tangents, the test angles.
      if (slope > 35.01) {
        EXPECT_EQ(m, kRock) << x << "," << y << " slope " << slope;
      }
      if (m == kRock) {
        EXPECT_GT(slope, 34.99) << x << "," << y;
      }
      if (m == kSnow) {
        EXPECT_GE(t, 0.8 - 1e-9) << x << "," << y;
        EXPECT_LT(slope, 35.01) << x << "," << y;
      }
      if (t > 0.8 + 1e-9 && slope < 34.99) {
        EXPECT_TRUE(m == kSnow || m == kWater) << x << "," << y;
      }
      if (m == kGrass) {
        EXPECT_LT(slope, 15.01);
        EXPECT_LT(t, 0.6 + 1e-9);
      }
    }
  std::printf("%s: water %zu, grass %zu, soil %zu, rock %zu, snow %zu\n", name.c_str(), counts[0],
              counts[1], counts[2], counts[3], counts[4]);
  EXPECT_GT(counts[kRock], 0u);
  EXPECT_GT(counts[kSnow], 0u);
  EXPECT_GT(counts[kGrass], 0u);

  // Deterministic, also through another reader of the same file.
  auto other = dem->reopen();
  ASSERT_TRUE(other.ok());
  auto again = classifyDem(*other.value());
  ASSERT_TRUE(again.ok());
  EXPECT_EQ(again->classes, map->classes);
}

TEST(DemClassification, CraterLakeFollowsSlopesAndHeights) {
  checkAgainstSlopes("crater_lake_0513.bt");
  // The lake surface (exactly flat at 1883 m, far above the lowest 5 %) is water: raster
  // column 450, row 300.
  auto dem = openDem("crater_lake_0513.bt");
  auto map = classifyDem(*dem);
  ASSERT_TRUE(map.ok());
  EXPECT_EQ(map->at(450, 512 - 300), kWater);
  EXPECT_EQ(map->at(480, 512 - 250), kWater);
}

TEST(DemClassification, ZionFollowsSlopesAndHeightsAndVoidsAreWater) {
  checkAgainstSlopes("zion_srtm3_utm12_30m.tif");
}

TEST(DemClassification, ReportsProgressOverBothPasses) {
  struct Counting : Progress {
    uint64_t total = 0, done = 0;
    void begin(std::string_view, uint64_t t) override { total = t; }
    void advance(uint64_t a) override { done += a; }
    void end() override {}
  } progress;
  auto dem = openDem("crater_lake_0513.bt");
  ASSERT_TRUE(classifyDem(*dem, &progress).ok());
  EXPECT_EQ(progress.total, 2u * 513u);
  EXPECT_EQ(progress.done, progress.total);
}

}  // namespace
}  // namespace terralod
