// Where the builder puts each mip's texels (its rule, docs/format.md "Mip placement"), as the
// renderer works it out from the tile sizes per level.

#include "terralod/render/texture_placement.h"

#include <gtest/gtest.h>

namespace terralod {
namespace {

TEST(TexturePlacement, LeavesAndResampledLevelsAreGlsOwn) {
  // 65 -> 33: neither twice minus one nor equal: resampled, every mip computed in place.
  const uint32_t sizes[] = {33, 65};
  const auto p = mipPlacements(sizes);
  ASSERT_EQ(p.size(), 2u);
  ASSERT_EQ(p[0].size(), 6u);  // 33, 16, 8, 4, 2, 1
  ASSERT_EQ(p[1].size(), 7u);
  for (uint32_t level = 0; level < 2; ++level)
    for (uint32_t m = 0; m < p[level].size(); ++m)
      EXPECT_EQ(p[level][m], (MipPlacement{1, sizes[level], m})) << level << " " << m;
  EXPECT_FALSE(needsPiecewiseSampling(p[0]));
}

TEST(TexturePlacement, UnresampledChainsAreMosaicsOfTheLeavesMips) {
  // Source-limited levels keep their children's texels: 257 = 2 * 129 - 1 = 4 * 65 - 3.
  const uint32_t sizes[] = {257, 129, 65};
  const auto p = mipPlacements(sizes);
  // Level 1 (129): mips 1..6 are two leaves' mips side by side; mip 7 (one texel) its own.
  for (uint32_t m = 1; m <= 6; ++m) EXPECT_EQ(p[1][m], (MipPlacement{2, 65, m})) << m;
  EXPECT_EQ(p[1][7], (MipPlacement{1, 129, 7}));
  // Level 0 (257): mips 1..6 four leaves across, mip 7 two of level 1's mip 7, mip 8 its own.
  for (uint32_t m = 1; m <= 6; ++m) EXPECT_EQ(p[0][m], (MipPlacement{4, 65, m})) << m;
  EXPECT_EQ(p[0][7], (MipPlacement{2, 129, 7}));
  EXPECT_EQ(p[0][8], (MipPlacement{1, 257, 8}));
  // Level 0 of every tile is edge-aligned as a whole (its mosaic shares border texels).
  EXPECT_EQ(p[0][0], (MipPlacement{1, 257, 0}));
  EXPECT_TRUE(needsPiecewiseSampling(p[0]));
  EXPECT_TRUE(needsPiecewiseSampling(p[1]));
  EXPECT_FALSE(needsPiecewiseSampling(p[2]));
}

TEST(TexturePlacement, HalvingParentsUseTheirChildrensNextMip) {
  const uint32_t sizes[] = {65, 65, 65};
  const auto p = mipPlacements(sizes);
  // Level 1: mip m is two leaves' mip m + 1; mip 6 (one texel) would need half-texel pieces.
  for (uint32_t m = 1; m <= 5; ++m) EXPECT_EQ(p[1][m], (MipPlacement{2, 65, m + 1})) << m;
  EXPECT_EQ(p[1][6], (MipPlacement{1, 65, 6}));
  // Level 0: mip m is four leaves' mip m + 2 where they have it.
  for (uint32_t m = 1; m <= 4; ++m) EXPECT_EQ(p[0][m], (MipPlacement{4, 65, m + 2})) << m;
  EXPECT_EQ(p[0][5], (MipPlacement{2, 65, 6}));
  // Halving shifts texels very little: GL's own sampling is kept.
  EXPECT_FALSE(needsPiecewiseSampling(p[0]));
  EXPECT_FALSE(needsPiecewiseSampling(p[1]));
}

TEST(TexturePlacement, HalvingAboveAnUnresampledChainNeedsPiecewiseSampling) {
  const uint32_t sizes[] = {129, 129, 65};
  const auto p = mipPlacements(sizes);
  EXPECT_EQ(p[0][1], (MipPlacement{4, 65, 2}));  // level 1's mip 2: two leaves' mip 2
  EXPECT_TRUE(needsPiecewiseSampling(p[0]));
}

TEST(TexturePlacement, PackedTableMarksTheLevelsToSamplePieceByPiece) {
  const uint32_t color[] = {257, 129, 65}, normal[] = {33, 65, 65};
  const auto table = packPlacements(color, normal);
  ASSERT_EQ(table.size(), 3 * 2 * kPlacementEntries);
  auto entry = [&](size_t level, size_t kind, size_t m) {
    return table[(level * 2 + kind) * kPlacementEntries + m];
  };
  EXPECT_EQ(entry(0, 0, 0), 0x80000000u | 257u << 8);  // colour, root: piecewise
  EXPECT_EQ(entry(0, 0, 3), 2u | 3u << 4 | 65u << 8);  // four pieces of 65 at their mip 3
  EXPECT_EQ(entry(0, 1, 0), 33u << 8);                 // normal, root: GL's own
  EXPECT_EQ(entry(1, 1, 2), 1u | 3u << 4 | 65u << 8);  // halving: two pieces at mip 3
  EXPECT_EQ(entry(2, 0, 15), 0u);                      // past the last mip
}

}  // namespace
}  // namespace terralod
