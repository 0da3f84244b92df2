#pragma once
// Where a terralod camera is in a 3D Tiles export (issue 24), so that a 3D Tiles client looks
// at the exported tiles from where `terralod render --eye --target` looks at the tileset
// (scripts/cesium-screenshot.sh). The export's placement is rebuilt from what its tileset.json
// records (extras.source_grid) through the same function the export used, and the camera goes
// through it: the eye as every vertex did (PROJ to Earth-centred coordinates), the view
// direction and up through the local frame at the eye.

#include <array>
#include <string>

#include <nlohmann/json_fwd.hpp>

#include "terralod/core/result.h"
#include "terralod/core/source_grid.h"
#include "terralod/raster/earth_placement.h"

namespace terralod::tiles3d {

/// Where tilesets without a place are put (a tangent plane; documented in README): longitude
/// and latitude in degrees.
inline constexpr double kDefaultLongitude = 0.0, kDefaultLatitude = 0.0;

struct ExportPlacement {
  EarthPlacement placement;
  std::string unplacedReason;  ///< empty: placed through the source's georeferencing
};

/// The export's placement of a source grid: through its georeferencing, or, where it has none
/// (no geotransform, no CRS, a local CRS), the tangent plane at the default longitude and
/// latitude, with the reason.
ExportPlacement placementOf(const SourceGrid& grid, const std::string& subject);

/// The source grid an export recorded in its tileset.json (extras.source_grid); fails, naming
/// `subject`, when the record is missing or malformed (not a terralod export).
Result<SourceGrid> exportedSourceGrid(const nlohmann::json& tileset, const std::string& subject);

struct EarthCamera {
  std::array<double, 3> eye{};        ///< Earth-centred, Earth-fixed metres (EPSG:4978)
  std::array<double, 3> direction{};  ///< unit, ECEF: towards the target
  std::array<double, 3> up{};         ///< unit, ECEF, at right angles to the direction
  double longitude = 0, latitude = 0, height = 0;  ///< the eye's, WGS 84 (degrees, metres)
};

/// terralod's camera (local metres, up along local z) on Earth. Fails when PROJ fails or the
/// eye and target coincide, or the view is straight up or down.
Result<EarthCamera> earthCamera(const EarthPlacement& placement, const std::array<double, 3>& eye,
                                const std::array<double, 3>& target);

}  // namespace terralod::tiles3d
