#pragma once
// Where a tileset's local metres lie on Earth (3D Tiles export, issue 24). Local coordinates
// are terralod's world coordinates: x east and y north in metres from the source's south-west
// sample (grid point (x / spacingX, y / spacingY), a pixel centre), z up, the source's heights.
// They go through the source's georeferencing (geotransform and CRS) and PROJ to
// Earth-centred, Earth-fixed coordinates (EPSG:4978, metres). Heights are taken as heights
// above the source CRS's ellipsoid: a DEM whose heights are above a geoid (SRTM: EGM96) lands
// within the geoid's undulation of its place (under 110 m anywhere; about 23 m at Zion).
//
// Sources without a place (no geotransform, no CRS, or a local engineering CRS) get none: the
// caller may fall back to tangentPlane(), a documented default.

#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <string>

#include <glm/mat4x4.hpp>

#include "terralod/core/result.h"
#include "terralod/core/source_grid.h"

namespace terralod {

class EarthPlacement {
 public:
  /// Through the grid's georeferencing. Fails, naming `subject`, when it has no geotransform or
  /// no CRS, when the CRS is a local one, or when PROJ has no transformation to EPSG:4978.
  static Result<EarthPlacement> of(const SourceGrid& grid, const std::string& subject);

  /// The default for sources without a place: the local x-y plane tangent to the WGS 84
  /// ellipsoid at (longitude, latitude) (degrees), the local origin there at height 0, x east,
  /// y north. Exact for the tangent plane (no curvature).
  static EarthPlacement tangentPlane(double longitudeDeg, double latitudeDeg);

  ~EarthPlacement();
  EarthPlacement(EarthPlacement&&) noexcept;
  EarthPlacement& operator=(EarthPlacement&&) noexcept;

  /// ECEF metres of local points, in place. Fails when PROJ fails for any of them.
  Status toEarth(std::span<std::array<double, 3>> points) const;

  /// The local frame at (x, y, z) as a column-major matrix: ECEF ≈ M · (dx, dy, dz, 1) for a
  /// small offset (dx, dy, dz) from the point. Its columns are the derivatives along local x and
  /// y (through the projection: scale and convergence included) and the ellipsoid's up normal,
  /// its translation the point's ECEF position.
  Result<glm::dmat4> frameAt(double x, double y, double z) const;

 private:
  struct Impl;
  explicit EarthPlacement(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> mImpl;
};

/// WGS 84 geodetic (degrees, metres above the ellipsoid) to ECEF metres.
std::array<double, 3> wgs84ToEcef(double longitudeDeg, double latitudeDeg, double height);

/// ECEF metres to WGS 84 geodetic (longitude, latitude in degrees, height in metres).
std::array<double, 3> ecefToWgs84(const std::array<double, 3>& ecef);

}  // namespace terralod
