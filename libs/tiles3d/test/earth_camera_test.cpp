// A terralod camera on Earth as a 3D Tiles client places it: the eye where the export puts the
// same local point, the view direction towards where it puts the target, up along the
// ellipsoid's normal turned square to the view; and the source grid read back from what an
// export's tileset.json records.

#include "terralod/tiles3d/earth_camera.h"

#include <gtest/gtest.h>
#include <ogr_spatialref.h>

#include <cmath>
#include <nlohmann/json.hpp>

namespace terralod::tiles3d {
namespace {

double dot(const std::array<double, 3>& a, const std::array<double, 3>& b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

// UTM zone 12 N, 30 m cells, as Zion's DEM.
SourceGrid utmGrid() {
  SourceGrid g;
  g.columns = 1128;
  g.rows = 1428;
  g.spacingX = g.spacingY = 30;
  g.geoTransform = {309000, 30, 0, 4150000, 0, -30};
  g.hasGeoTransform = true;
  OGRSpatialReference utm;
  utm.importFromEPSG(32612);
  char* wkt = nullptr;
  utm.exportToWkt(&wkt);
  g.crsWkt = wkt;
  CPLFree(wkt);
  return g;
}

TEST(EarthCamera, LooksFromTheEyesPlaceTowardsTheTargetsWithUpSquareToIt) {
  const ExportPlacement placed = placementOf(utmGrid(), "zion");
  ASSERT_EQ(placed.unplacedReason, "");
  const std::array<double, 3> eye = {12000, 2000, 3500}, target = {12100, 2300, 3400};
  auto camera = earthCamera(placed.placement, eye, target);
  ASSERT_TRUE(camera.ok()) << camera.error().message;
  std::array<double, 3> points[2] = {eye, target};
  ASSERT_TRUE(placed.placement.toEarth(points).ok());
  EXPECT_NEAR(camera->eye[0], points[0][0], 1e-6);
  EXPECT_NEAR(camera->eye[2], points[0][2], 1e-6);
  // A target 330 m away: the chord through the placement and the frame's direction agree to
  // well under a pixel's angle.
  std::array<double, 3> chord = {points[1][0] - points[0][0], points[1][1] - points[0][1],
                                 points[1][2] - points[0][2]};
  const double length = std::sqrt(dot(chord, chord));
  EXPECT_GT(dot(chord, camera->direction) / length, std::cos(1e-4));
  EXPECT_NEAR(dot(camera->direction, camera->direction), 1.0, 1e-12);
  EXPECT_NEAR(dot(camera->up, camera->up), 1.0, 1e-12);
  EXPECT_NEAR(dot(camera->up, camera->direction), 0.0, 1e-12);
  // Up leans towards the sky: along the eye's position from the Earth's centre, roughly.
  const double r = std::sqrt(dot(camera->eye, camera->eye));
  EXPECT_GT(dot(camera->up, camera->eye) / r, 0.9);
  EXPECT_NEAR(camera->height, 3500.0, 1e-3);
  EXPECT_NEAR(camera->longitude, -113.0, 0.5);
  EXPECT_NEAR(camera->latitude, 37.4, 0.5);
}

TEST(EarthCamera, RefusesAViewWithoutADirectionOrUp) {
  const ExportPlacement placed = placementOf(utmGrid(), "zion");
  EXPECT_FALSE(earthCamera(placed.placement, {1, 2, 3}, {1, 2, 3}).ok());
  EXPECT_FALSE(earthCamera(placed.placement, {1, 2, 3}, {1, 2, 0}).ok());
}

TEST(EarthCamera, WithoutACrsTheDefaultPlaneAndWhy) {
  SourceGrid g = utmGrid();
  g.crsWkt.clear();
  const ExportPlacement placed = placementOf(g, "plain.asc");
  EXPECT_NE(placed.unplacedReason, "");
  auto camera = earthCamera(placed.placement, {0, 0, 100}, {0, 1000, 0});
  ASSERT_TRUE(camera.ok());
  EXPECT_NEAR(camera->longitude, kDefaultLongitude, 1e-9);
  EXPECT_NEAR(camera->latitude, kDefaultLatitude, 1e-9);
}

TEST(EarthCamera, TheSourceGridComesBackFromAnExportsExtras) {
  const SourceGrid g = utmGrid();
  const nlohmann::json tileset = {{"extras",
                                   {{"source_grid",
                                     {{"columns", g.columns},
                                      {"rows", g.rows},
                                      {"spacing", {g.spacingX, g.spacingY}},
                                      {"crs_wkt", g.crsWkt},
                                      {"geotransform", g.geoTransform}}}}}};
  auto back = exportedSourceGrid(tileset, "tileset.json");
  ASSERT_TRUE(back.ok()) << back.error().message;
  EXPECT_EQ(back->columns, g.columns);
  EXPECT_EQ(back->rows, g.rows);
  EXPECT_EQ(back->geoTransform, g.geoTransform);
  EXPECT_TRUE(back->hasGeoTransform);
  EXPECT_EQ(back->crsWkt, g.crsWkt);
  nlohmann::json broken = tileset;
  broken["extras"]["source_grid"]["spacing"] = {30, -1};
  EXPECT_FALSE(exportedSourceGrid(broken, "tileset.json").ok());
  auto missing = exportedSourceGrid(nlohmann::json::object(), "tileset.json");
  ASSERT_FALSE(missing.ok());
  EXPECT_NE(missing.error().message.find("tileset.json"), std::string::npos);
}

}  // namespace
}  // namespace terralod::tiles3d
