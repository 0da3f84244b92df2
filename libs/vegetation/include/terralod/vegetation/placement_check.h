#pragma once
// Checks a placement the way a user sees it: laid over a tiling, every plant where it lands.
// `terralod vegetation points` writes the same points; the tests and bench/ measure them.

#include <cstdint>
#include <vector>

#include "terralod/vegetation/tile_objects.h"
#include "terralod/vegetation/wang_tiling.h"

namespace terralod::veg {

/// A plant of a tiling, in tiling coordinates (metres from the south-west corner).
struct TilingPoint {
  double x = 0, y = 0;
  const PlacedObject* object = nullptr;  ///< in its prototile's list
  uint32_t tileX = 0, tileY = 0;         ///< the tile its centre is in
};

/// Every plant of a tiling once (from the tile its centre is in), row by row.
std::vector<TilingPoint> tilingPoints(const std::vector<PrototileContent>& tiles, float tileSize,
                                      const WangTiling& tiling);

struct PlacementReport {
  uint64_t objects = 0;
  uint64_t tightOverlaps = 0;    ///< pairs closer than the sum of their tight radii
  uint64_t packingOverlaps = 0;  ///< … packing radii, centres in the same or edge-adjacent tiles
  uint64_t packingAcrossCorners = 0;  ///< … packing radii, centres in diagonal tiles (allowed)
  uint64_t tightAcrossCorners = 0;    ///< plants whose tight disk crosses two edges of their tile
  double minTightRatio = 0;           ///< smallest distance / (sum of tight radii) over close pairs
  double minPackingRatio = 0;         ///< the same for packing radii, edge-adjacent or same tile
  /// Plants per square metre by where their centre is in its tile: farther than `band` from
  /// every edge, within `band` of one edge, within `band` of two (a corner).
  double band = 0, interiorDensity = 0, edgeDensity = 0, cornerDensity = 0;
};

/// `band` ≤ 0: twice the largest packing radius.
PlacementReport checkPlacement(const std::vector<PrototileContent>& tiles, float tileSize,
                               const WangTiling& tiling, double band = 0);

/// Plant density over the tile square folded from a tiling (bins × bins, row-major from the
/// south), normalised to a mean of 1: sparse corners or edges show as dark rims.
std::vector<double> foldedDensity(const std::vector<TilingPoint>& points, float tileSize, int bins);

}  // namespace terralod::veg
