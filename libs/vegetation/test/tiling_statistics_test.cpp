#include "terralod/vegetation/tiling_statistics.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <set>

namespace terralod::veg {
namespace {

constexpr double kChance = 1.0 / kWangPrototiles;

// The exact statistics of our tiling's interior, from its structure alone (wang_tiling.h): every
// tile's north colour is an independent fair bit n(x, y); the south colour is n(x, y−1) and the
// west colour the west neighbour's east = south ^ north, n(x−1, y−1) ^ n(x−1, y). Enumerates the
// 2^16 bit patterns of the 4 × 4 window whose tile (2, 2) and all eight neighbours it fixes.
struct ExactLocal {
  std::array<std::array<double, 3>, 3> pSame{};  ///< [dy + 1][dx + 1]
  double withSameNeighbour = 0;                  ///< of an interior tile
};

ExactLocal exactLocalStatistics() {
  ExactLocal exact;
  for (uint32_t bits = 0; bits < (1u << 16); ++bits) {
    auto n = [&](int x, int y) { return int(bits >> (y * 4 + x)) & 1; };
    auto tile = [&](int x, int y) {
      const int west = n(x - 1, y - 1) ^ n(x - 1, y), south = n(x, y - 1), north = n(x, y);
      const int k = west << 2 | south << 1 | north;
      const TileEdges e = prototileEdges(k);  // the model agrees with the prototile set
      EXPECT_TRUE(e.west == west && e.south == south && e.north == north);
      return k;
    };
    const int centre = tile(2, 2);
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx)
        exact.pSame[dy + 1][dx + 1] += tile(2 + dx, 2 + dy) == centre;
    exact.withSameNeighbour += tile(1, 2) == centre || tile(3, 2) == centre ||
                               tile(2, 1) == centre || tile(2, 3) == centre;
  }
  for (auto& row : exact.pSame)
    for (double& p : row) p /= 65536.0;
  exact.withSameNeighbour /= 65536.0;
  return exact;
}

TEST(TilingStatistics, EveryLagOneApartIsTheSamePrototileWithChanceProbability) {
  // Neighbours share edge colours, yet the same prototile turns up next to a tile exactly as
  // often as under independent choice, in all eight directions: the expected autocorrelation
  // at lag 1 is 0, like at every larger lag (those tiles share no bits at all).
  const ExactLocal exact = exactLocalStatistics();
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx)
      EXPECT_DOUBLE_EQ(exact.pSame[dy + 1][dx + 1], dx == 0 && dy == 0 ? 1.0 : kChance)
          << "lag " << dx << "," << dy;
  // But the events are not independent: fewer tiles than under independent choice have a
  // neighbour of their own prototile: 399/1024 = 0.390 against 1 − (7/8)^4 = 0.414.
  EXPECT_DOUBLE_EQ(exact.withSameNeighbour, 399.0 / 1024);
}

TEST(TilingStatistics, OurSameNeighbourFrequencyIsChance) {
  for (uint64_t seed : {1ull, 2ull, 3ull}) {
    const NeighbourStats s = neighbourStats(toGrid(WangTiling(256, 256, seed)));
    EXPECT_EQ(s.sameEitherExpected, kChance);
    EXPECT_NEAR(s.sameEast, kChance, 0.01) << "seed " << seed;
    EXPECT_NEAR(s.sameNorth, kChance, 0.01) << "seed " << seed;
    // The exact interior value (0.390) up to the border tiles and sampling noise.
    EXPECT_NEAR(s.withSameNeighbour, exactLocalStatistics().withSameNeighbour, 0.01);
    EXPECT_NEAR(s.withSameNeighbourExpected, 1 - std::pow(7.0 / 8, 4), 0.01);
  }
  // The laid and the looked-up tiling are the same tiling, so the same statistics.
  const NeighbourStats laid = neighbourStats(toGrid(scanlineTiling(64, 48, 9)));
  const NeighbourStats looked = neighbourStats(toGrid(WangTiling(64, 48, 9)));
  EXPECT_EQ(laid.sameEast, looked.sameEast);
  EXPECT_EQ(laid.largestClump, looked.largestClump);
}

TEST(TilingStatistics, OurRepeatsConcentrateOnPrototilesThatMatchThemselves) {
  // Only a prototile with west = east can have itself as east neighbour (with probability 1/4:
  // the neighbour's south and north must match as well), only one with south = north as north
  // neighbour: repeats as frequent as chance, but gathered on fewer prototiles, so clumps
  // (§7) are fewer and larger than under independent choice.
  const TileGrid grid = toGrid(WangTiling(256, 256, 1));
  std::array<double, kWangPrototiles> tiles{}, sameEast{}, sameNorth{};
  for (uint32_t y = 0; y + 1 < grid.height; ++y)
    for (uint32_t x = 0; x + 1 < grid.width; ++x) {
      const int k = grid.at(x, y);
      tiles[k] += 1;
      sameEast[k] += grid.at(x + 1, y) == k;
      sameNorth[k] += grid.at(x, y + 1) == k;
    }
  for (int k = 0; k < kWangPrototiles; ++k) {
    const TileEdges e = prototileEdges(k);
    EXPECT_NEAR(sameEast[k] / tiles[k], e.west == e.east ? 0.25 : 0.0, 0.03) << "prototile " << k;
    EXPECT_NEAR(sameNorth[k] / tiles[k], e.south == e.north ? 0.25 : 0.0, 0.03)
        << "prototile " << k;
  }
  for (uint64_t seed : {1ull, 2ull, 3ull}) {
    const NeighbourStats ours = neighbourStats(toGrid(WangTiling(256, 256, seed)));
    const NeighbourStats chance = neighbourStats(independentTiling(256, 256, 8, seed));
    EXPECT_LT(ours.withSameNeighbour, chance.withSameNeighbour - 0.01) << "seed " << seed;
    EXPECT_GT(ours.meanClump, chance.meanClump + 0.04) << "seed " << seed;
  }
}

TEST(TilingStatistics, OurAutocorrelationIsFlatOffTheOrigin) {
  const ExactLocal exact = exactLocalStatistics();
  const Autocorrelation ac = autocorrelation(toGrid(WangTiling(256, 256, 1)), 16);
  ASSERT_EQ(ac.values.size(), 33u * 33u);
  EXPECT_DOUBLE_EQ(ac.at(0, 0), 1.0);
  EXPECT_LT(ac.maxAbsFromLag(2), 0.05);
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx) {
      const double expected = (exact.pSame[dy + 1][dx + 1] - kChance) / (1 - kChance);
      EXPECT_NEAR(ac.at(dx, dy), expected, 0.01) << "lag " << dx << "," << dy;
      EXPECT_EQ(ac.at(dx, dy), ac.at(-dx, -dy));
    }
  EXPECT_LT(ac.maxAbsOffOrigin, 0.05);
  EXPECT_LT(ac.meanAbsOnAxes, 0.01);
  EXPECT_LT(ac.meanAbsOffAxes, 0.01);
}

TEST(TilingStatistics, TheHierarchicalComparisonIsPlaid) {
  const Autocorrelation ours = autocorrelation(toGrid(WangTiling(256, 256, 1)), 16);
  const Autocorrelation other = autocorrelation(hierarchicalTiling(256, 256, 1), 16);
  // Measured (seed 1): along the axes 0.216 against 0.073 off them; ours 0.0015 both ways.
  EXPECT_GT(other.meanAbsOnAxes, 2.5 * other.meanAbsOffAxes);
  EXPECT_GT(other.meanAbsOnAxes, 50 * ours.meanAbsOnAxes);
  EXPECT_GT(other.maxAbsOffOrigin, 0.8);
}

TEST(TilingStatistics, AConstantTilingCorrelatesEverywhere) {
  for (int count : {1, 8}) {
    const TileGrid grid = sampleGrid(20, 12, count, [](uint32_t, uint32_t) { return 0; });
    const Autocorrelation ac = autocorrelation(grid, 5);
    for (double v : ac.values) EXPECT_DOUBLE_EQ(v, 1.0) << "count " << count;
    const NeighbourStats s = neighbourStats(grid);
    EXPECT_EQ(s.sameEast, 1.0);
    EXPECT_EQ(s.sameNorth, 1.0);
    EXPECT_EQ(s.largestClump, 240u);
    EXPECT_EQ(s.meanClump, 240.0);
  }
}

TEST(TilingStatistics, ACheckerboardAlternatesInSign) {
  const TileGrid grid = sampleGrid(16, 16, 2, [](uint32_t x, uint32_t y) { return (x + y) & 1; });
  const Autocorrelation ac = autocorrelation(grid, 4);
  for (int dy = -4; dy <= 4; ++dy)
    for (int dx = -4; dx <= 4; ++dx)
      EXPECT_DOUBLE_EQ(ac.at(dx, dy), (dx + dy) % 2 == 0 ? 1.0 : -1.0) << dx << "," << dy;
  EXPECT_DOUBLE_EQ(ac.meanAbsOnAxes, 1.0);
  const NeighbourStats s = neighbourStats(grid);
  EXPECT_EQ(s.sameEast, 0.0);
  EXPECT_EQ(s.sameNorth, 0.0);
  EXPECT_EQ(s.withSameNeighbour, 0.0);
  EXPECT_EQ(s.largestClump, 1u);

  // Vertical stripes: same going north, never going east; every column one clump.
  const NeighbourStats stripes =
      neighbourStats(sampleGrid(10, 7, 2, [](uint32_t x, uint32_t) { return x & 1; }));
  EXPECT_EQ(stripes.sameEast, 0.0);
  EXPECT_EQ(stripes.sameNorth, 1.0);
  EXPECT_EQ(stripes.largestClump, 7u);
  EXPECT_EQ(stripes.meanClump, 7.0);
}

TEST(TilingStatistics, IndependentTilesAreAtChance) {
  const TileGrid grid = independentTiling(256, 256, 8, 4);
  const NeighbourStats s = neighbourStats(grid);
  EXPECT_NEAR(s.sameEast, kChance, 0.01);
  EXPECT_NEAR(s.withSameNeighbour, s.withSameNeighbourExpected, 0.01);
  EXPECT_LT(autocorrelation(grid, 8).maxAbsOffOrigin, 0.05);
}

TEST(TilingHierarchical, TypesFollowTheTwoAdicStructure) {
  EXPECT_EQ(hierarchicalTileType(1, 1), 3);   // level-0 cross facing north-east
  EXPECT_EQ(hierarchicalTileType(3, 3), 0);   // its neighbour across (2, 2), facing south-west
  EXPECT_EQ(hierarchicalTileType(2, 2), 7);   // level-1 cross facing north-east
  EXPECT_EQ(hierarchicalTileType(4, 4), 3);   // level 2: even again
  EXPECT_EQ(hierarchicalTileType(2, 1), 9);   // vertical arm, level-1 line, pointing south
  EXPECT_EQ(hierarchicalTileType(2, 3), 11);  // the same line pointing north
  EXPECT_EQ(hierarchicalTileType(1, 2), 13);  // horizontal arm, level-1 line, pointing west
  EXPECT_EQ(hierarchicalTileType(uint64_t(1) << 63, 1), 9);  // no shift beyond 63 bits
  EXPECT_EQ(hierarchicalTileType(uint64_t(1) << 63, uint64_t(1) << 63), 7);

  // Crosses wherever the trailing zero counts agree: a third of the tiles (Σ 4^−(k+1)).
  const TileGrid grid = hierarchicalTiling(256, 256, 0);
  ASSERT_EQ(grid.prototileCount, kHierarchicalTileTypes);
  std::set<int> types;
  int crosses = 0;
  for (uint8_t t : grid.prototiles) {
    types.insert(t);
    crosses += t < 8;
  }
  EXPECT_EQ(types.size(), size_t(kHierarchicalTileTypes));
  EXPECT_NEAR(crosses / 65536.0, 1.0 / 3, 0.002);
  EXPECT_EQ(grid.at(0, 0), 3);
  EXPECT_NE(hierarchicalTiling(64, 64, 1).prototiles, hierarchicalTiling(64, 64, 2).prototiles);
}

TEST(TilingPictures, SizesAndColours) {
  const TileGrid grid = toGrid(WangTiling(32, 32, 1));
  const RgbImage small = renderTiling(grid, 8);
  ASSERT_EQ(small.width, 256);
  ASSERT_EQ(small.height, 256);
  ASSERT_EQ(small.rgb.size(), 256u * 256 * 3);
  // North up: the top-left pixel is tile (0, 31); tiles of different prototiles differ.
  const TileGrid two = sampleGrid(2, 1, 8, [](uint32_t x, uint32_t) { return int(x) * 5; });
  const RgbImage twoImage = renderTiling(two, 3);
  EXPECT_EQ(twoImage.width, 6);
  EXPECT_NE(std::vector<uint8_t>(twoImage.pixel(0, 0), twoImage.pixel(0, 0) + 3),
            std::vector<uint8_t>(twoImage.pixel(3, 0), twoImage.pixel(3, 0) + 3));
  int sameAsTopLeftTile = 0;
  for (uint32_t x = 0; x < 32; ++x)
    for (uint32_t y = 0; y < 32; ++y)
      if (grid.at(x, y) == grid.at(0, 31))
        sameAsTopLeftTile += std::equal(small.pixel(0, 0), small.pixel(0, 0) + 3,
                                        small.pixel(int(x) * 8 + 4, int(31 - y) * 8 + 4));
  EXPECT_EQ(sameAsTopLeftTile,
            std::count(grid.prototiles.begin(), grid.prototiles.end(), uint8_t(grid.at(0, 31))));

  // The heat map: red at the origin, white at 0, blue below 0.
  const TileGrid checker = sampleGrid(8, 8, 2, [](uint32_t x, uint32_t y) { return (x + y) & 1; });
  const RgbImage heat = renderAutocorrelation(autocorrelation(checker, 2), 4, 1.0);
  ASSERT_EQ(heat.width, 20);
  ASSERT_EQ(heat.height, 20);
  EXPECT_GT(heat.pixel(10, 10)[0], 150);  // (0, 0): +1, red
  EXPECT_LT(heat.pixel(10, 10)[2], 60);
  EXPECT_LT(heat.pixel(14, 10)[0], 60);  // (1, 0): −1, blue
  EXPECT_GT(heat.pixel(14, 10)[2], 150);
  Autocorrelation zero;
  zero.values.assign(1, 0.0);
  EXPECT_EQ(renderAutocorrelation(zero, 1, 1.0).rgb, std::vector<uint8_t>(3, 255));

  // Figure 4's layout: four 256-pixel panels and five gaps; two 264-pixel maps below.
  const TilingFigure figure = tilingFigure();
  EXPECT_EQ(figure.image.width, 4 * 256 + 5 * 8);
  EXPECT_EQ(figure.image.height, 8 + 256 + 8 + 33 * 8 + 8);
  EXPECT_EQ(figure.image.rgb.size(), size_t(figure.image.width) * figure.image.height * 3);
  EXPECT_EQ(figure.heatScale, figure.comparison.maxAbsOffOrigin);
  EXPECT_EQ(figure.ours.maxLag, 16);
}

}  // namespace
}  // namespace terralod::veg
