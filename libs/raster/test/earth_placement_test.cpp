#include "terralod/raster/earth_placement.h"

#include <gtest/gtest.h>

#include <cmath>

#include "temp_dir.h"
#include "terralod/raster/dem_reader.h"

namespace terralod {
namespace {

using test::testData;

SourceGrid gridOf(const std::string& name) {
  auto dem = DemReader::open(testData(name), {});
  EXPECT_TRUE(dem.ok());
  const DemInfo& info = (*dem)->info();
  return {info.columns,         info.rows,  info.spacingX, info.spacingY, info.geoTransform,
          info.hasGeoTransform, info.crsWkt};
}

double length(const glm::dvec4& v) {
  return std::sqrt(v.x * v.x + v.y * v.y + v.z * v.z);
}
double dot(const glm::dvec4& a, const glm::dvec4& b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}

TEST(EarthPlacement, Wgs84AndEcefRoundTrip) {
  const auto equator = wgs84ToEcef(0, 0, 0);
  EXPECT_NEAR(equator[0], 6378137.0, 1e-6);
  EXPECT_NEAR(wgs84ToEcef(0, 90, 0)[2], 6356752.314245, 1e-5);
  for (const auto& [lon, lat, h] : std::vector<std::array<double, 3>>{
           {-113.04, 37.32, 1500}, {151.2, -33.9, -20}, {0, 89.99, 8000}, {-179.5, 0.1, 3}}) {
    const auto g = ecefToWgs84(wgs84ToEcef(lon, lat, h));
    EXPECT_NEAR(g[0], lon, 1e-9);
    EXPECT_NEAR(g[1], lat, 1e-9);
    EXPECT_NEAR(g[2], h, 1e-4);
  }
}

TEST(EarthPlacement, AUtmGridLandsWhereGdalSaysItsCentreIs) {
  // zion_srtm3_utm12_30m.tif: gdalinfo puts its centre, pixel (564, 714)'s corner, at
  // 113d 2'41.24"W, 37d19'22.79"N (to a hundredth of a second: 0.3 m); local x, y of that
  // corner are 563.5 and 713.5 cells.
  const SourceGrid grid = gridOf("zion_srtm3_utm12_30m.tif");
  auto placement = EarthPlacement::of(grid, "zion.tlod");
  ASSERT_TRUE(placement.ok()) << placement.error().message;
  std::array<std::array<double, 3>, 1> centre = {{{563.5 * 30, 713.5 * 30, 1500}}};
  ASSERT_TRUE(placement->toEarth(centre));
  const auto g = ecefToWgs84(centre[0]);
  EXPECT_NEAR(g[0], -(113 + 2 / 60.0 + 41.24 / 3600), 0.005 / 3600);
  EXPECT_NEAR(g[1], 37 + 19 / 60.0 + 22.79 / 3600, 0.005 / 3600);
  EXPECT_NEAR(g[2], 1500, 1e-3);

  // The frame there: x and y a metre each (UTM's scale within 0.1 %), nearly east and north
  // (the zone's convergence, under 2 degrees here), up the ellipsoid's normal.
  auto frame = placement->frameAt(563.5 * 30, 713.5 * 30, 1500);
  ASSERT_TRUE(frame.ok());
  const glm::dvec4 ex = (*frame)[0], ey = (*frame)[1], up = (*frame)[2];
  EXPECT_NEAR(length(ex), 1.0, 1e-3);
  EXPECT_NEAR(length(ey), 1.0, 1e-3);
  EXPECT_NEAR(length(up), 1.0, 1e-12);
  EXPECT_NEAR(dot(ex, ey), 0.0, 1e-6);
  EXPECT_NEAR(dot(ex, up), 0.0, 1e-6);
  EXPECT_NEAR(dot(ey, up), 0.0, 1e-6);
  // The frame predicts a point 100 m away to a few millimetres.
  std::array<std::array<double, 3>, 1> near = {{{563.5 * 30 + 100, 713.5 * 30 + 60, 1510}}};
  ASSERT_TRUE(placement->toEarth(near));
  const glm::dvec4 predicted = *frame * glm::dvec4(100, 60, 10, 1);
  EXPECT_NEAR(predicted.x, near[0][0], 0.01);
  EXPECT_NEAR(predicted.y, near[0][1], 0.01);
  EXPECT_NEAR(predicted.z, near[0][2], 0.01);
}

TEST(EarthPlacement, AGeographicGridAgreesWithTheProjectedOne) {
  // The same terrain in EPSG:4326: its south-west sample where its geotransform says.
  const SourceGrid grid = gridOf("zion_srtm3.tif");
  auto placement = EarthPlacement::of(grid, "zion_geo.tlod");
  ASSERT_TRUE(placement.ok()) << placement.error().message;
  std::array<std::array<double, 3>, 1> sw = {{{0, 0, 0}}};
  ASSERT_TRUE(placement->toEarth(sw));
  const auto g = ecefToWgs84(sw[0]);
  const auto& t = grid.geoTransform;
  EXPECT_NEAR(g[0], t[0] + 0.5 * t[1], 1e-9);
  EXPECT_NEAR(g[1], t[3] + (grid.rows - 0.5) * t[5], 1e-9);
}

TEST(EarthPlacement, TheTangentPlaneDefault) {
  const EarthPlacement p = EarthPlacement::tangentPlane(10, 45);
  std::array<std::array<double, 3>, 2> q = {{{0, 0, 0}, {0, 0, 100}}};
  ASSERT_TRUE(p.toEarth(q));
  const auto g0 = ecefToWgs84(q[0]), g1 = ecefToWgs84(q[1]);
  EXPECT_NEAR(g0[0], 10, 1e-9);
  EXPECT_NEAR(g0[1], 45, 1e-9);
  EXPECT_NEAR(g0[2], 0, 1e-6);
  EXPECT_NEAR(g1[2], 100, 1e-6);
  auto frame = p.frameAt(0, 0, 0);
  ASSERT_TRUE(frame.ok());
  EXPECT_NEAR(dot((*frame)[0], (*frame)[1]), 0, 1e-8);
  EXPECT_NEAR((*frame)[0].z, 0, 1e-8) << "x runs east";
}

TEST(EarthPlacement, RefusesGridsWithoutAPlace) {
  SourceGrid grid = gridOf("zion_srtm3_utm12_30m.tif");
  SourceGrid noTransform = grid;
  noTransform.hasGeoTransform = false;
  auto a = EarthPlacement::of(noTransform, "a.tlod");
  ASSERT_FALSE(a.ok());
  EXPECT_EQ(a.error().message, "a.tlod: has no georeferencing (no geotransform)");
  SourceGrid noCrs = grid;
  noCrs.crsWkt.clear();
  EXPECT_EQ(EarthPlacement::of(noCrs, "b.tlod").error().message,
            "b.tlod: has no coordinate reference system");
  SourceGrid local = grid;
  local.crsWkt = R"(LOCAL_CS["site grid",UNIT["metre",1],AXIS["x",EAST],AXIS["y",NORTH]])";
  EXPECT_EQ(EarthPlacement::of(local, "c.tlod").error().message,
            "c.tlod: has a local CRS, which places it nowhere on Earth");
  SourceGrid garbage = grid;
  garbage.crsWkt = "not a CRS";
  auto d = EarthPlacement::of(garbage, "d.tlod");
  ASSERT_FALSE(d.ok());
  EXPECT_EQ(d.error().message.rfind("d.tlod: its CRS cannot be read", 0), 0u) << d.error().message;
}

}  // namespace
}  // namespace terralod
