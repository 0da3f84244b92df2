#include "terralod/tiles3d/earth_camera.h"

#include <cmath>
#include <span>

#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <nlohmann/json.hpp>

namespace terralod::tiles3d {

ExportPlacement placementOf(const SourceGrid& grid, const std::string& subject) {
  auto placed = EarthPlacement::of(grid, subject);
  if (placed.ok()) return {std::move(placed).value(), ""};
  return {EarthPlacement::tangentPlane(kDefaultLongitude, kDefaultLatitude),
          placed.error().message};
}

Result<SourceGrid> exportedSourceGrid(const nlohmann::json& tileset, const std::string& subject) {
  const auto bad = [&](const std::string& problem) {
    return makeError(subject, problem + " (not a terralod 3D Tiles export?)");
  };
  if (!tileset.is_object()) return bad("is not a JSON object");
  const auto extras = tileset.find("extras");
  if (extras == tileset.end() || !extras->is_object()) return bad("has no \"extras\"");
  const auto g = extras->find("source_grid");
  if (g == extras->end() || !g->is_object()) return bad("has no \"extras\".\"source_grid\"");
  SourceGrid grid;
  const auto columns = g->find("columns"), rows = g->find("rows"), spacing = g->find("spacing"),
             wkt = g->find("crs_wkt");
  const auto positive = [](const nlohmann::json& v) {
    return v.is_number() && std::isfinite(v.get<double>()) && v.get<double>() > 0;
  };
  const auto count = [&](const nlohmann::json::const_iterator& v) {
    return v != g->end() && v->is_number_integer() && v->get<int64_t>() > 0 &&
           v->get<int64_t>() <= INT32_MAX;
  };
  if (!count(columns) || !count(rows))
    return bad("\"source_grid\" has no valid \"columns\" and \"rows\"");
  if (spacing == g->end() || !spacing->is_array() || spacing->size() != 2 ||
      !positive((*spacing)[0]) || !positive((*spacing)[1]))
    return bad("\"source_grid\" has no valid \"spacing\" (two positive numbers)");
  if (wkt == g->end() || !wkt->is_string())
    return bad("\"source_grid\" has no \"crs_wkt\" (text, empty for none)");
  grid.columns = int32_t(columns->get<int64_t>());
  grid.rows = int32_t(rows->get<int64_t>());
  grid.spacingX = (*spacing)[0].get<double>();
  grid.spacingY = (*spacing)[1].get<double>();
  grid.crsWkt = wkt->get<std::string>();
  if (const auto t = g->find("geotransform"); t != g->end()) {
    if (!t->is_array() || t->size() != 6)
      return bad("\"source_grid\".\"geotransform\" is not six numbers");
    for (size_t i = 0; i < 6; ++i) {
      if (!(*t)[i].is_number() || !std::isfinite((*t)[i].get<double>()))
        return bad("\"source_grid\".\"geotransform\" is not six numbers");
      grid.geoTransform[i] = (*t)[i].get<double>();
    }
    grid.hasGeoTransform = true;
  }
  return grid;
}

Result<EarthCamera> earthCamera(const EarthPlacement& placement, const std::array<double, 3>& eye,
                                const std::array<double, 3>& target) {
  const glm::dvec3 e(eye[0], eye[1], eye[2]), t(target[0], target[1], target[2]);
  const glm::dvec3 look = t - e;
  if (!(glm::length(look) > 0))
    return makeError("camera", "the eye and the target are the same point");
  auto frame = placement.frameAt(e.x, e.y, e.z);
  if (!frame) return frame.error();
  // Directions map through the frame's linear part (the derivatives along local x and y, and
  // the ellipsoid's normal for local z).
  const glm::dmat3 linear(*frame);
  const glm::dvec3 direction = glm::normalize(linear * look);
  const glm::dvec3 zenith = glm::normalize(linear * glm::dvec3(0, 0, 1));
  const glm::dvec3 right = glm::cross(direction, zenith);
  if (!(glm::length(right) > 1e-9))
    return makeError("camera", "looks straight up or down (no up direction)");
  const glm::dvec3 up = glm::normalize(glm::cross(glm::normalize(right), direction));
  EarthCamera camera;
  std::array<double, 3> ecef = eye;
  if (Status s = placement.toEarth(std::span(&ecef, 1)); !s) return s.error();
  camera.eye = ecef;
  camera.direction = {direction.x, direction.y, direction.z};
  camera.up = {up.x, up.y, up.z};
  const auto geodetic = ecefToWgs84(ecef);
  camera.longitude = geodetic[0];
  camera.latitude = geodetic[1];
  camera.height = geodetic[2];
  return camera;
}

}  // namespace terralod::tiles3d
