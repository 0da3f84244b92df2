#include "terralod/raster/synthetic_terrain.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <vector>

#include "temp_dir.h"
#include "terralod/raster/dem_reader.h"
#include "terralod/raster/synthetic_dem_writer.h"

namespace terralod {
namespace {

using test::TempDir;

std::vector<float> window(const SyntheticTerrain& t, int64_t c0, int64_t r0, int32_t w, int32_t h) {
  std::vector<float> v(size_t(w) * size_t(h));
  t.fillWindow(c0, r0, w, h, v.data());
  return v;
}

TEST(SyntheticTerrain, SameSeedSameHeightsOtherSeedOtherTerrain) {
  const SyntheticTerrain a(7, 1.0), b(7, 1.0), c(8, 1.0);
  const auto wa = window(a, 1000, 2000, 300, 40), wb = window(b, 1000, 2000, 300, 40);
  const auto wc = window(c, 1000, 2000, 300, 40);
  EXPECT_EQ(wa, wb);
  size_t differing = 0;
  for (size_t i = 0; i < wa.size(); ++i) differing += std::fabs(wa[i] - wc[i]) > 1.0f;
  EXPECT_GT(differing, wa.size() * 9 / 10);
}

TEST(SyntheticTerrain, AWindowIsTheSameWhereverItIsCutFrom) {
  // Windows that straddle the 256-column evaluation chunks and the 8-cell lattice at odd
  // offsets must agree bit for bit with a bigger window and with single samples.
  const SyntheticTerrain t(3, 2.0);
  const int64_t c0 = 250, r0 = 13;
  const int32_t w = 600, h = 21;
  const auto big = window(t, c0, r0, w, h);
  const auto part = window(t, c0 + 7, r0 + 5, 301, 9);
  for (int r = 0; r < 9; ++r)
    for (int c = 0; c < 301; ++c)
      ASSERT_EQ(part[size_t(r) * 301 + c], big[size_t(r + 5) * w + c + 7]) << c << "," << r;
  for (int k = 0; k < 50; ++k) {
    const int c = (k * 37) % w, r = (k * 11) % h;
    ASSERT_EQ(t.height(c0 + c, r0 + r), big[size_t(r) * w + c]);
  }
}

TEST(SyntheticTerrain, HasMountainsValleysAndFlatsAtRealisticHeights) {
  // 40 km at 40 m: enough to cross several flats, hills and ranges.
  const SyntheticTerrain t(1, 40.0);
  const int32_t n = 1000;
  const auto v = window(t, 0, 0, n, n);
  const auto [lo, hi] = std::minmax_element(v.begin(), v.end());
  EXPECT_GT(*lo, 0.0f);
  EXPECT_LT(*hi, 2500.0f);
  EXPECT_GT(*hi - *lo, 800.0f) << "no mountains";
  // Local relief over 400 m squares (10 x 10 samples): flats have little, mountains much.
  size_t flat = 0, steep = 0, blocks = 0;
  for (int by = 0; by + 10 <= n; by += 10)
    for (int bx = 0; bx + 10 <= n; bx += 10) {
      float a = 1e9f, b = -1e9f;
      for (int y = by; y < by + 10; ++y)
        for (int x = bx; x < bx + 10; ++x) {
          a = std::min(a, v[size_t(y) * n + x]);
          b = std::max(b, v[size_t(y) * n + x]);
        }
      ++blocks;
      flat += b - a < 5.0f;
      steep += b - a > 100.0f;
    }
  EXPECT_GT(flat, blocks / 20) << "no flats";
  EXPECT_GT(steep, blocks / 20) << "no steep mountain slopes";
}

TEST(SyntheticDemWriter, WritesAGeoTiffThatReadsBackInWorldCoordinates) {
  TempDir dir;
  SyntheticDemOptions o;
  o.output = dir.file("synth.tif");
  o.columns = 300;  // not a multiple of the 256-sample tiles
  o.rows = 270;
  o.seed = 5;
  o.spacing = 2.5;
  NullProgress progress;
  ASSERT_TRUE(writeSyntheticDem(o, progress).ok());
  auto reader = DemReader::open(o.output, {});
  ASSERT_TRUE(reader.ok()) << reader.error().message;
  const DemInfo& info = (*reader)->info();
  EXPECT_EQ(info.columns, 300);
  EXPECT_EQ(info.rows, 270);
  EXPECT_DOUBLE_EQ(info.spacingX, 2.5);
  EXPECT_DOUBLE_EQ(info.spacingY, 2.5);
  EXPECT_EQ(info.spacingSource, "local CRS");
  std::vector<float> grid(300 * 270);
  ASSERT_TRUE((*reader)->readWindow(0, 0, 300, 270, grid.data()).ok());
  // Grid rows run south to north; the generator's rows north to south.
  const SyntheticTerrain t(5, 2.5);
  for (int gy : {0, 1, 137, 269})
    for (int x : {0, 255, 256, 299})
      EXPECT_EQ(grid[size_t(gy) * 300 + x], t.height(x, 269 - gy)) << x << "," << gy;
  // Nothing but the output is left in the directory.
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir.path()), {}), 1);
}

TEST(SyntheticDemWriter, RejectsBadOptionsAndLeavesNothing) {
  TempDir dir;
  NullProgress progress;
  SyntheticDemOptions o;
  o.output = dir.file("a.tif");
  o.columns = o.rows = 1;
  EXPECT_FALSE(writeSyntheticDem(o, progress).ok());
  o.columns = o.rows = kMaxSyntheticSide + 1;
  EXPECT_FALSE(writeSyntheticDem(o, progress).ok());
  o.columns = o.rows = 64;
  o.output = dir.file("missing-dir/a.tif");
  const Status s = writeSyntheticDem(o, progress);
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.error().message.find("missing-dir/a.tif"), std::string::npos) << s.error().message;
  EXPECT_TRUE(std::filesystem::is_empty(dir.path()));
}

}  // namespace
}  // namespace terralod
