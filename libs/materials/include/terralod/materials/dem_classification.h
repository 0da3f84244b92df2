#pragma once
// Materials from the DEM itself, for a VIPM build without a categorical raster.
//
// Every grid point gets one of five fixed materials. The table is always the same, all five
// entries are kept even when a DEM uses only some of them (an unused material is valid, just
// never referenced), and index = id:
//
//   index/id  name    colour (sRGB)
//   0         water   ( 58,  96, 128)
//   1         grass   ( 96, 124,  60)
//   2         soil    (128, 104,  76)
//   3         rock    (112, 108, 104)
//   4         snow    (236, 240, 244)
//
// Inputs per point: the slope angle, from central differences with the DEM's spacing
// (spacingX, spacingY; one-sided on the DEM's edges, and towards a void neighbour), and the
// relative height t = (h - min) / (max - min) over the DEM's exact height range (0 when the
// DEM is flat). The first rule that matches wins:
//
//   1. a void (nodata) point                                   -> water (DEM voids are most
//      often sea or lakes; the builder fills the heights themselves separately)
//   2. slope >= 35 degrees                                     -> rock
//   3. slope < 1 degree and t < 0.05 (flat in the lowest 5 %)  -> water
//   4. the 5x5 samples around the point (clamped at the edges) all have exactly the same
//      height: a flat area at least 5 samples across, e.g. a lake surface   -> water
//   5. t >= 0.80 (snow line at 80 % of the height range)       -> snow
//   6. slope >= 15 degrees                                     -> soil
//   7. t >= 0.60 (gentle but high ground)                      -> soil
//   8. otherwise (gentle and low)                              -> grass
//
// The DEM is read twice in bands of rows (once for its height range, once to classify), so
// only a few hundred rows of heights are in memory at once; the map is 1 byte per point.
// The result depends only on the heights and spacing: deterministic.

#include "terralod/core/progress.h"
#include "terralod/core/result.h"
#include "terralod/materials/material.h"
#include "terralod/raster/dem_reader.h"

namespace terralod {

/// The fixed thresholds of the rules above.
struct DemClassificationRules {
  static constexpr double kRockSlopeDegrees = 35.0;
  static constexpr double kSoilSlopeDegrees = 15.0;
  static constexpr double kWaterSlopeDegrees = 1.0;
  static constexpr double kWaterBelow = 0.05;  ///< of the height range
  static constexpr double kSnowLine = 0.80;    ///< of the height range
  static constexpr double kHighGround = 0.60;  ///< of the height range
  static constexpr int kFlatRadius = 2;        ///< exactly flat (2r+1)^2 window: water
};

/// Indices of the fixed table (also the ids).
enum DemMaterial : uint8_t { kWater = 0, kGrass = 1, kSoil = 2, kRock = 3, kSnow = 4 };

/// The five fixed materials, in index order.
std::vector<Material> demClassificationMaterials();

/// Classifies every grid point of `dem` by the rules above. Fails only when reading fails.
Result<MaterialMap> classifyDem(const DemReader& dem, Progress* progress = nullptr);

}  // namespace terralod
