#include "terralod/raster/earth_placement.h"

#include <ogr_spatialref.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "gdal_support.h"

namespace terralod {
namespace {

constexpr double kA = 6378137.0;            // WGS 84 semi-major axis, metres
constexpr double kF = 1.0 / 298.257223563;  // flattening
constexpr double kE2 = kF * (2.0 - kF);     // first eccentricity squared
constexpr double kDegree = std::numbers::pi / 180.0;

std::array<double, 3> upAt(double longitudeDeg, double latitudeDeg) {
  const double l = longitudeDeg * kDegree, p = latitudeDeg * kDegree;
  return {std::cos(p) * std::cos(l), std::cos(p) * std::sin(l), std::sin(p)};
}

}  // namespace

std::array<double, 3> wgs84ToEcef(double longitudeDeg, double latitudeDeg, double height) {
  const double l = longitudeDeg * kDegree, p = latitudeDeg * kDegree;
  const double n = kA / std::sqrt(1.0 - kE2 * std::sin(p) * std::sin(p));
  return {(n + height) * std::cos(p) * std::cos(l), (n + height) * std::cos(p) * std::sin(l),
          (n * (1.0 - kE2) + height) * std::sin(p)};
}

std::array<double, 3> ecefToWgs84(const std::array<double, 3>& e) {
  const double r = std::hypot(e[0], e[1]);
  const double longitude = std::atan2(e[1], e[0]);
  // Fixed-point iteration on latitude (converges to well under a millimetre in a few steps
  // for points near the surface).
  double latitude = std::atan2(e[2], r * (1.0 - kE2)), height = 0.0;
  for (int i = 0; i < 8; ++i) {
    const double s = std::sin(latitude);
    const double n = kA / std::sqrt(1.0 - kE2 * s * s);
    height = std::abs(std::cos(latitude)) > 1e-12 ? r / std::cos(latitude) - n
                                                  : std::abs(e[2]) - n * (1.0 - kE2);
    latitude = std::atan2(e[2], r * (1.0 - kE2 * n / (n + height)));
  }
  return {longitude / kDegree, latitude / kDegree, height};
}

struct EarthPlacement::Impl {
  struct TransformDeleter {
    void operator()(OGRCoordinateTransformation* t) const {
      OGRCoordinateTransformation::DestroyCT(t);
    }
  };
  // Through the grid (PROJ) or, when null, the tangent plane at `origin` with `axes`.
  std::unique_ptr<OGRCoordinateTransformation, TransformDeleter> toEcef;
  SourceGrid grid;
  std::array<double, 3> origin{};
  std::array<std::array<double, 3>, 3> axes{};  // east, north, up
};

EarthPlacement::EarthPlacement(std::unique_ptr<Impl> impl) : mImpl(std::move(impl)) {}
EarthPlacement::~EarthPlacement() = default;
EarthPlacement::EarthPlacement(EarthPlacement&&) noexcept = default;
EarthPlacement& EarthPlacement::operator=(EarthPlacement&&) noexcept = default;

Result<EarthPlacement> EarthPlacement::of(const SourceGrid& grid, const std::string& subject) {
  gdal::ensureRegistered();
  gdal::QuietErrors quiet;
  if (!grid.hasGeoTransform) return makeError(subject, "has no georeferencing (no geotransform)");
  if (grid.crsWkt.empty()) return makeError(subject, "has no coordinate reference system");
  OGRSpatialReference source, earth;
  if (source.importFromWkt(grid.crsWkt.c_str()) != OGRERR_NONE)
    return makeError(subject, "its CRS cannot be read (" + gdal::lastErrorMessage() + ")");
  if (source.IsLocal())
    return makeError(subject, "has a local CRS, which places it nowhere on Earth");
  if (earth.importFromEPSG(4978) != OGRERR_NONE)
    return makeError(subject, "PROJ has no EPSG:4978 (" + gdal::lastErrorMessage() + ")");
  source.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
  earth.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
  auto impl = std::make_unique<Impl>();
  impl->toEcef.reset(OGRCreateCoordinateTransformation(&source, &earth));
  if (!impl->toEcef)
    return makeError(subject, "PROJ cannot transform its CRS to Earth-centred coordinates (" +
                                  gdal::lastErrorMessage() + ")");
  impl->grid = grid;
  return EarthPlacement(std::move(impl));
}

EarthPlacement EarthPlacement::tangentPlane(double longitudeDeg, double latitudeDeg) {
  auto impl = std::make_unique<Impl>();
  impl->origin = wgs84ToEcef(longitudeDeg, latitudeDeg, 0.0);
  const double l = longitudeDeg * kDegree, p = latitudeDeg * kDegree;
  impl->axes = {{{-std::sin(l), std::cos(l), 0.0},
                 {-std::sin(p) * std::cos(l), -std::sin(p) * std::sin(l), std::cos(p)},
                 upAt(longitudeDeg, latitudeDeg)}};
  return EarthPlacement(std::move(impl));
}

Status EarthPlacement::toEarth(std::span<std::array<double, 3>> points) const {
  const Impl& m = *mImpl;
  if (!m.toEcef) {
    for (auto& q : points) {
      const std::array<double, 3> local = q;
      for (int k = 0; k < 3; ++k)
        q[size_t(k)] = m.origin[size_t(k)] + m.axes[0][size_t(k)] * local[0] +
                       m.axes[1][size_t(k)] * local[1] + m.axes[2][size_t(k)] * local[2];
    }
    return {};
  }
  const SourceGrid& g = m.grid;
  const auto& t = g.geoTransform;
  const bool southUp = t[5] > 0;
  std::vector<double> x(points.size()), y(points.size()), z(points.size());
  for (size_t i = 0; i < points.size(); ++i) {
    // Grid point (column, row from the south) at the raster pixel's centre.
    const double column = points[i][0] / g.spacingX, fromSouth = points[i][1] / g.spacingY;
    const double row = southUp ? fromSouth : double(g.rows - 1) - fromSouth;
    x[i] = t[0] + (column + 0.5) * t[1] + (row + 0.5) * t[2];
    y[i] = t[3] + (column + 0.5) * t[4] + (row + 0.5) * t[5];
    z[i] = points[i][2];
  }
  std::vector<int> ok(points.size(), 0);
  gdal::QuietErrors quiet;
  const bool done = m.toEcef->Transform(points.size(), x.data(), y.data(), z.data(), ok.data());
  for (size_t i = 0; i < points.size(); ++i) {
    if (!done || !ok[i] || !std::isfinite(x[i]) || !std::isfinite(y[i]) || !std::isfinite(z[i]))
      return Error{"PROJ cannot place local point (" + std::to_string(points[i][0]) + ", " +
                   std::to_string(points[i][1]) + ") on Earth"};
    points[i] = {x[i], y[i], z[i]};
  }
  return {};
}

Result<glm::dmat4> EarthPlacement::frameAt(double x, double y, double z) const {
  // Central differences over a grid cell along x and y; up is the ellipsoid's normal there.
  const double hx = mImpl->toEcef ? mImpl->grid.spacingX : 1.0;
  const double hy = mImpl->toEcef ? mImpl->grid.spacingY : 1.0;
  std::array<std::array<double, 3>, 5> p = {
      {{x, y, z}, {x + hx, y, z}, {x - hx, y, z}, {x, y + hy, z}, {x, y - hy, z}}};
  if (Status s = toEarth(p); !s) return s.error();
  const std::array<double, 3> geodetic = ecefToWgs84(p[0]);
  const std::array<double, 3> up = upAt(geodetic[0], geodetic[1]);
  glm::dmat4 m(1.0);
  for (int k = 0; k < 3; ++k) {
    m[0][k] = (p[1][size_t(k)] - p[2][size_t(k)]) / (2.0 * hx);
    m[1][k] = (p[3][size_t(k)] - p[4][size_t(k)]) / (2.0 * hy);
    m[2][k] = up[size_t(k)];
    m[3][k] = p[0][size_t(k)];
  }
  return m;
}

}  // namespace terralod
