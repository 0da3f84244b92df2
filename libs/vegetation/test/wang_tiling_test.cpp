#include "terralod/vegetation/wang_tiling.h"

#include <gtest/gtest.h>

#include <set>
#include <tuple>

namespace terralod::veg {
namespace {

TEST(WangTiles, EveryWestSouthPairHasTwoPrototilesDifferingInNorth) {
  const auto& set = prototileSet();
  for (int west = 0; west < 2; ++west)
    for (int south = 0; south < 2; ++south) {
      std::set<int> norths;
      for (const TileEdges& e : set)
        if (e.west == west && e.south == south) norths.insert(e.north);
      EXPECT_EQ(norths, (std::set<int>{0, 1})) << "west " << west << " south " << south;
    }
  std::set<std::tuple<int, int, int, int>> distinct;
  for (const TileEdges& e : set) distinct.insert({e.north, e.east, e.south, e.west});
  EXPECT_EQ(distinct.size(), 8u);
}

TEST(WangTiles, TheScanlineTilingIsValidAndEveryTileCanBeLookedUpAlone) {
  for (uint64_t seed : {1ull, 2ull, 977ull}) {
    const LaidTiling laid = scanlineTiling(301, 203, seed);
    ASSERT_TRUE(tilingIsValid(laid));
    const WangTiling lookup(301, 203, seed);
    for (uint32_t y = 0; y < laid.height; ++y)
      for (uint32_t x = 0; x < laid.width; ++x)
        ASSERT_EQ(lookup.at(x, y), laid.at(x, y)) << "seed " << seed << " tile " << x << "," << y;
  }
}

TEST(WangTiles, ABrokenEdgeMakesATilingInvalid) {
  LaidTiling laid = scanlineTiling(16, 16, 5);
  ASSERT_TRUE(tilingIsValid(laid));
  laid.prototiles[5 * 16 + 7] ^= 1;  // flips the north colour: the tile above no longer fits
  EXPECT_FALSE(tilingIsValid(laid));
}

TEST(WangTiles, SeedsGiveDifferentTilingsAndEveryPrototileAppears) {
  const WangTiling a(64, 64, 1), b(64, 64, 2);
  int differ = 0, counts[8] = {};
  for (uint32_t y = 0; y < 64; ++y)
    for (uint32_t x = 0; x < 64; ++x) {
      differ += a.at(x, y) != b.at(x, y);
      ++counts[a.at(x, y)];
    }
  EXPECT_GT(differ, 64 * 64 / 2);
  for (int c : counts) EXPECT_NEAR(c, 64 * 64 / 8, 120);
}

}  // namespace
}  // namespace terralod::veg
