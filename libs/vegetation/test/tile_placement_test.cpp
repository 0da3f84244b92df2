#include "terralod/vegetation/tile_placement.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "terralod/vegetation/placement_check.h"
#include "terralod/vegetation/wang_tiling.h"

namespace terralod::veg {
namespace {

// Two species with fixed radii: a quick stand-in for the plant models.
float fixedRadius(Species s, int version) {
  return s == Species::kSunflower ? 0.30f + 0.01f * version : 0.12f + 0.005f * version;
}

PlacementSettings twoSpecies(uint64_t seed, uint32_t attempts = 2000) {
  PlacementSettings s;
  s.tileSize = 3;
  s.mix = {{Species::kSunflower, 1, 1.3f, 0.9f, 1.1f}, {Species::kGrass, 2, 1.2f, 0.9f, 1.1f}};
  s.attemptsPerVisit = attempts;
  s.seed = seed;
  return s;
}

const Placement& placed() {
  static const Placement p = [] {
    NullProgress quiet;
    return placeObjects(twoSpecies(7), fixedRadius, quiet);
  }();
  return p;
}

TEST(TilePlacement, EveryEdgeColourCarriesTheSameStraddlersInEveryPrototile) {
  const float size = 3;
  const auto& tiles = placed().tiles;
  size_t crossingPlants = 0;
  // For each side and colour: the plants crossing that side, in the frame of the tile on its
  // south/west, must be the same set in every prototile with that colour on either side.
  for (int vertical = 0; vertical < 2; ++vertical)
    for (int colour = 0; colour < 2; ++colour) {
      std::vector<std::vector<std::pair<float, float>>> seen;
      for (const PrototileContent& t : tiles) {
        for (int side = 0; side < 2; ++side) {  // 0: north/east side, 1: south/west side
          const int c = vertical ? (side == 0 ? t.edges.east : t.edges.west)
                                 : (side == 0 ? t.edges.north : t.edges.south);
          if (c != colour) continue;
          std::vector<std::pair<float, float>> crossing;
          for (const PlacedObject& o : t.objects) {
            const float across = vertical ? o.x : o.y, along = vertical ? o.y : o.x;
            const float line = side == 0 ? size : 0;
            if (std::abs(across - line) < o.tightRadius) crossing.push_back({along, across - line});
          }
          std::sort(crossing.begin(), crossing.end());
          seen.push_back(crossing);
        }
      }
      ASSERT_EQ(seen.size(), 8u);
      crossingPlants += seen[0].size();
      for (size_t k = 1; k < seen.size(); ++k) {
        ASSERT_EQ(seen[k].size(), seen[0].size());
        for (size_t i = 0; i < seen[0].size(); ++i) {  // a tile's shift rounds in float
          EXPECT_NEAR(seen[k][i].first, seen[0][i].first, 1e-5);
          EXPECT_NEAR(seen[k][i].second, seen[0][i].second, 1e-5);
        }
      }
    }
  EXPECT_GE(crossingPlants, 4u) << "too few plants cross edges: little was tested";
}

TEST(TilePlacement, OverATilingNoTightDisksOverlapAndPackingHoldsAcrossEdges) {
  const WangTiling tiling(24, 24, 3);
  const PlacementReport r = checkPlacement(placed().tiles, 3, tiling);
  EXPECT_GT(r.objects, 24u * 24u * 10u);
  EXPECT_EQ(r.tightOverlaps, 0u);
  EXPECT_EQ(r.packingOverlaps, 0u);
  EXPECT_EQ(r.tightAcrossCorners, 0u);
  EXPECT_GE(r.minTightRatio, 1.0);
  EXPECT_GE(r.minPackingRatio, 1.0);
}

TEST(TilePlacement, TheCheckSeesPlantsThatIgnoreTheirNeighbours) {
  // The same plants with every edge straddler dropped from the prototiles it was copied
  // into: across edges, plants now overlap, and the check must say so.
  std::vector<PrototileContent> tiles = placed().tiles;
  for (PrototileContent& t : tiles)
    std::erase_if(t.objects, [](const PlacedObject& o) { return !centredIn(o, 3); });
  // Shift every tile's plants so that those near the west edge move onto the east edge's.
  for (PrototileContent& t : tiles)
    for (PlacedObject& o : t.objects) o.x = std::fmod(o.x + 1.37f, 3.0f);
  const PlacementReport r = checkPlacement(tiles, 3, WangTiling(24, 24, 3));
  EXPECT_GT(r.tightOverlaps + r.packingOverlaps, 0u);
}

TEST(TilePlacement, IsTheSameForTheSameSeed) {
  NullProgress quiet;
  const Placement a = placeObjects(twoSpecies(11, 500), fixedRadius, quiet);
  const Placement b = placeObjects(twoSpecies(11, 500), fixedRadius, quiet);
  const Placement c = placeObjects(twoSpecies(12, 500), fixedRadius, quiet);
  EXPECT_EQ(a.tiles, b.tiles);
  EXPECT_NE(a.tiles, c.tiles);
}

}  // namespace
}  // namespace terralod::veg
