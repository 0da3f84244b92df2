#include "terralod/materials/material_raster.h"

#include <gdal.h>
#include <gdal_priv.h>
#include <gtest/gtest.h>
#include <ogr_spatialref.h>

#include <cmath>
#include <fstream>
#include <functional>
#include <set>

#include "temp_dir.h"

namespace terralod {
namespace {

const std::string kClasses = test::testData("zion_landcover_classes.tif");

std::unique_ptr<DemReader> openDem(const std::string& path) {
  auto dem = DemReader::open(path, {});
  EXPECT_TRUE(dem.ok()) << (dem.ok() ? "" : dem.error().message);
  return dem.ok() ? std::move(dem).value() : nullptr;
}

// Writes a one-band GeoTIFF whose pixel (c, r) holds value(c, r). `epsg` 0: no CRS; an empty
// geotransform: no georeferencing.
void writeRaster(const std::string& path, int w, int h, GDALDataType type,
                 const std::function<double(int, int)>& value, std::vector<double> gt,
                 int epsg = 32612, std::optional<double> nodata = {},
                 const std::function<void(GDALRasterBand*)>& extra = {}) {
  GDALAllRegister();
  GDALDriver* driver = GetGDALDriverManager()->GetDriverByName("GTiff");
  GDALDataset* ds = driver->Create(path.c_str(), w, h, 1, type, nullptr);
  ASSERT_NE(ds, nullptr);
  if (!gt.empty()) ds->SetGeoTransform(gt.data());
  if (epsg) {
    OGRSpatialReference srs;
    srs.importFromEPSG(epsg);
    ds->SetSpatialRef(&srs);
  }
  std::vector<double> values(size_t(w) * h);
  for (int r = 0; r < h; ++r)
    for (int c = 0; c < w; ++c) values[size_t(r) * w + c] = value(c, r);
  GDALRasterBand* band = ds->GetRasterBand(1);
  if (nodata) band->SetNoDataValue(*nodata);
  if (extra) extra(band);
  ASSERT_EQ(band->RasterIO(GF_Write, 0, 0, w, h, values.data(), w, h, GDT_Float64, 0, 0, nullptr),
            CE_None);
  GDALClose(ds);
}

// A small DEM in UTM 12N: 20 x 20 samples at 30 m, a tilted plane.
const std::vector<double> kDemGeo = {300000, 30, 0, 4100600, 0, -30};
std::string writeSmallDem(const test::TempDir& dir, bool georeferenced = true) {
  const std::string path = dir.file(georeferenced ? "dem.tif" : "dem_plain.tif");
  writeRaster(
      path, 20, 20, GDT_Float32, [](int c, int r) { return 1000.0 + c + r; },
      georeferenced ? kDemGeo : std::vector<double>{}, georeferenced ? 32612 : 0);
  return path;
}

std::string writeText(const test::TempDir& dir, const std::string& name, const std::string& text) {
  std::ofstream(dir.file(name)) << text;
  return dir.file(name);
}

// The value of `path` at raster pixel (c, r), read through GDAL.
double pixel(const std::string& path, int c, int r) {
  GDALDatasetH ds = GDALOpen(path.c_str(), GA_ReadOnly);
  double v = NAN;
  EXPECT_EQ(
      GDALRasterIO(GDALGetRasterBand(ds, 1), GF_Read, c, r, 1, 1, &v, 1, 1, GDT_Float64, 0, 0),
      CE_None);
  GDALClose(ds);
  return v;
}

TEST(MaterialRaster, ZionClassesOntoTheirOwnGridAreTheIdentity) {
  auto dem = openDem(test::testData("zion_srtm3_utm12_30m.tif"));
  ASSERT_TRUE(dem);
  auto map = readMaterialRaster(kClasses, *dem);
  ASSERT_TRUE(map.ok()) << map.error().message;
  ASSERT_EQ(map->materials.size(), 5u);
  // Names and colours come from the file itself (classify writes them), no palette given.
  EXPECT_EQ(map->materials[0].id, 1);
  EXPECT_EQ(map->materials[0].name, "vegetation");
  EXPECT_EQ(map->materials[2].name, "pale sandstone");
  EXPECT_EQ(map->materials[1].color, (std::array<uint8_t, 3>{170, 120, 105}));
  GDALDatasetH ds = GDALOpen(kClasses.c_str(), GA_ReadOnly);
  const int rows = GDALGetRasterYSize(ds), cols = GDALGetRasterXSize(ds);
  std::vector<uint8_t> raster(size_t(cols) * rows);
  ASSERT_EQ(GDALRasterIO(GDALGetRasterBand(ds, 1), GF_Read, 0, 0, cols, rows, raster.data(), cols,
                         rows, GDT_Byte, 0, 0),
            CE_None);
  GDALClose(ds);
  for (int gy = 0; gy < rows; ++gy)
    for (int gx = 0; gx < cols; ++gx)
      ASSERT_EQ(map->materials[map->at(gx, gy)].id, raster[size_t(rows - 1 - gy) * cols + gx])
          << gx << "," << gy;
}

TEST(MaterialRaster, ZionClassesOntoAGeographicDem) {
  const std::string demPath = test::testData("zion_srtm3.tif");
  auto dem = openDem(demPath);
  ASSERT_TRUE(dem);
  auto map = readMaterialRaster(kClasses, *dem);
  ASSERT_TRUE(map.ok()) << map.error().message;
  ASSERT_EQ(map->columns, dem->info().columns);
  for (uint8_t c : map->classes) ASSERT_LT(c, map->materials.size());

  // Independently: each grid point's pixel centre in longitude/latitude, projected to UTM
  // 12N, and the class pixel under it.
  const auto& g = dem->info().geoTransform;
  OGRSpatialReference wgs84, utm;
  wgs84.importFromEPSG(4326);
  wgs84.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
  utm.importFromEPSG(32612);
  utm.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
  std::unique_ptr<OGRCoordinateTransformation> toUtm(
      OGRCreateCoordinateTransformation(&wgs84, &utm));
  ASSERT_TRUE(toUtm);
  int checked = 0;
  for (int gy = 20; gy < map->rows - 20; gy += 37)
    for (int gx = 20; gx < map->columns - 20; gx += 41) {
      const int row = map->rows - 1 - gy;
      double x = g[0] + (gx + 0.5) * g[1], y = g[3] + (row + 0.5) * g[5];
      ASSERT_TRUE(toUtm->Transform(1, &x, &y));
      const int c = int(std::floor((x - 301905.0) / 30.0)),
                r = int(std::floor((4154085.0 - y) / 30.0));
      if (c < 0 || c >= 1128 || r < 0 || r >= 1428) continue;
      EXPECT_EQ(map->materials[map->at(gx, gy)].id, pixel(kClasses, c, r)) << gx << "," << gy;
      ++checked;
    }
  EXPECT_GT(checked, 50);
}

TEST(MaterialRaster, UncoveredPointsTakeTheNearestClass) {
  test::TempDir dir;
  auto dem = openDem(writeSmallDem(dir));
  // Covers the DEM's western 8 columns only; value 7 in the north half, 9 in the south, with a
  // nodata hole.
  const std::string path = dir.file("west.tif");
  writeRaster(
      path, 8, 20, GDT_Byte, [](int c, int r) { return c == 3 && r == 3 ? 0 : (r < 10 ? 7 : 9); },
      kDemGeo, 32612, 0.0);
  auto map = readMaterialRaster(path, *dem);
  ASSERT_TRUE(map.ok()) << map.error().message;
  ASSERT_EQ(map->materials.size(), 2u);
  EXPECT_EQ(map->materials[0].name, "class 7");
  EXPECT_EQ(map->materials[1].name, "class 9");
  for (int gy = 0; gy < 20; ++gy)
    for (int gx = 0; gx < 20; ++gx)
      EXPECT_EQ(map->at(gx, gy), 19 - gy < 10 ? 0 : 1) << gx << "," << gy;
}

TEST(MaterialRaster, PaletteNamesAndColoursWin) {
  test::TempDir dir;
  auto dem = openDem(writeSmallDem(dir));
  const std::string path = dir.file("two.tif");
  writeRaster(
      path, 20, 20, GDT_Byte, [](int c, int) { return c < 10 ? 3 : 5; }, kDemGeo);
  MaterialRasterOptions options;
  options.palettePath = writeText(dir, "p.json",
                                  R"({"classes": [{"value": 5, "name": "rock", "color": "#8A8580"},
                                     {"value": 4, "name": "unused", "color": [1, 2, 3]},
                                     {"value": 3, "name": "forest", "color": [34, 90, 40]}]})");
  auto map = readMaterialRaster(path, *dem, options);
  ASSERT_TRUE(map.ok()) << map.error().message;
  ASSERT_EQ(map->materials.size(), 2u);
  EXPECT_EQ(map->materials[0].name, "forest");
  EXPECT_EQ(map->materials[0].color, (std::array<uint8_t, 3>{34, 90, 40}));
  EXPECT_EQ(map->materials[1].name, "rock");
  EXPECT_EQ(map->materials[1].color, (std::array<uint8_t, 3>{0x8a, 0x85, 0x80}));
  EXPECT_EQ(map->at(0, 0), 0);
  EXPECT_EQ(map->at(19, 0), 1);
}

TEST(MaterialRaster, CategoryNamesAndColourTableOfTheRaster) {
  test::TempDir dir;
  auto dem = openDem(writeSmallDem(dir));
  const std::string path = dir.file("named.tif");
  writeRaster(
      path, 20, 20, GDT_Byte, [](int c, int) { return c < 10 ? 1 : 2; }, kDemGeo, 32612, {},
      [](GDALRasterBand* band) {
        const char* names[] = {"", "meadow", "scree", nullptr};
        band->SetCategoryNames(const_cast<char**>(names));
        GDALColorTable table;
        const GDALColorEntry a{0, 0, 0, 255}, b{10, 200, 30, 255}, c{90, 90, 90, 255};
        table.SetColorEntry(0, &a);
        table.SetColorEntry(1, &b);
        table.SetColorEntry(2, &c);
        band->SetColorTable(&table);
      });
  auto map = readMaterialRaster(path, *dem);
  ASSERT_TRUE(map.ok()) << map.error().message;
  ASSERT_EQ(map->materials.size(), 2u);
  EXPECT_EQ(map->materials[0].name, "meadow");
  EXPECT_EQ(map->materials[0].color, (std::array<uint8_t, 3>{10, 200, 30}));
  EXPECT_EQ(map->materials[1].name, "scree");
}

TEST(MaterialRaster, UngeoreferencedRasterOnUngeoreferencedDemOfTheSameSize) {
  test::TempDir dir;
  auto dem = openDem(writeSmallDem(dir, false));
  const std::string path = dir.file("plain.tif");
  writeRaster(
      path, 20, 20, GDT_Byte, [](int, int r) { return r == 0 ? 1 : 2; }, {}, 0);
  auto map = readMaterialRaster(path, *dem);
  ASSERT_TRUE(map.ok()) << map.error().message;
  EXPECT_EQ(map->at(5, 19), 0);  // raster row 0 is the north row
  EXPECT_EQ(map->at(5, 18), 1);
}

// Every refusal: one line that names the file and says what is wrong.
void expectError(const Result<MaterialMap>& map, const std::string& file,
                 const std::string& problem) {
  ASSERT_FALSE(map.ok());
  const std::string& m = map.error().message;
  EXPECT_NE(m.find(file), std::string::npos) << m;
  EXPECT_NE(m.find(problem), std::string::npos) << m;
  EXPECT_EQ(m.find('\n'), std::string::npos) << m;
}

TEST(MaterialRaster, BadInputGivesOneClearLine) {
  test::TempDir dir;
  auto dem = openDem(writeSmallDem(dir));
  auto read = [&](const std::string& path, const std::string& palette = "") {
    MaterialRasterOptions options;
    options.palettePath = palette;
    return readMaterialRaster(path, *dem, options);
  };
  expectError(read(dir.file("missing.tif")), "missing.tif", "no such file");
  const std::string text = writeText(dir, "notes.tif", "not a raster\n");
  expectError(read(text), "notes.tif", "not a raster GDAL can read");

  const std::string far = dir.file("far.tif");
  writeRaster(far, 20, 20, GDT_Byte, [](int, int) { return 1; }, {900000, 30, 0, 4100600, 0, -30});
  expectError(read(far), "far.tif", "does not overlap the DEM");
  const std::string europe = dir.file("europe.tif");  // another CRS, elsewhere on Earth
  writeRaster(
      europe, 20, 20, GDT_Byte, [](int, int) { return 1; }, {10, 0.01, 0, 50, 0, -0.01}, 4326);
  expectError(read(europe), "europe.tif", "does not overlap the DEM dem.tif");

  const std::string many = dir.file("many.tif");
  writeRaster(
      many, 20, 20, GDT_Byte, [](int c, int) { return c / 2; }, kDemGeo);
  expectError(read(many), "many.tif", "has 10 classes over the DEM; at most 8 are supported");

  const std::string floats = dir.file("floats.tif");
  writeRaster(
      floats, 20, 20, GDT_Float32, [](int c, int r) { return 0.25 * (c + r); }, kDemGeo);
  expectError(read(floats), "floats.tif", "looks like continuous data, not classes");
  const std::string wholeFloats = dir.file("whole_floats.tif");
  writeRaster(
      wholeFloats, 20, 20, GDT_Float32, [](int c, int) { return c < 10 ? 1 : 2; }, kDemGeo);
  EXPECT_TRUE(read(wholeFloats).ok());

  const std::string heights = dir.file("heights.tif");
  writeRaster(
      heights, 20, 20, GDT_Int16, [](int c, int r) { return c + 20 * r; }, kDemGeo);
  expectError(read(heights), "heights.tif", "more than 256 distinct values");
  expectError(read(heights), "heights.tif", "looks like continuous data, not classes");

  const std::string big = dir.file("big_values.tif");
  writeRaster(
      big, 20, 20, GDT_Int16, [](int c, int) { return c < 10 ? 1000 : 3; }, kDemGeo);
  expectError(read(big), "big_values.tif", "class values must be whole numbers 0..255");

  const std::string good = dir.file("good.tif");
  writeRaster(
      good, 20, 20, GDT_Byte, [](int c, int) { return c < 10 ? 1 : 2; }, kDemGeo);
  expectError(read(good, dir.file("none.json")), "none.json", "cannot read the palette");
  expectError(read(good, writeText(dir, "bad.json", "{\"classes\": [")), "bad.json",
              "not valid JSON");
  expectError(read(good, writeText(dir, "list.json", "[1, 2]")), "list.json",
              "no \"classes\" array");
  expectError(read(good, writeText(dir, "color.json",
                                   R"({"classes": [{"value": 1, "name": "a", "color": "red"}]})")),
              "color.json", "\"color\" must be");
  expectError(
      read(good, writeText(dir, "value.json",
                           R"({"classes": [{"value": 1.5, "name": "a", "color": [1,2,3]}]})")),
      "value.json", "\"value\" must be a whole number");
  expectError(read(good, writeText(dir, "twice.json",
                                   R"({"classes": [{"value": 1, "name": "a", "color": [1,2,3]},
                                      {"value": 1, "name": "b", "color": [1,2,3]}]})")),
              "twice.json", "twice");
  expectError(
      read(good, writeText(dir, "short.json",
                           R"({"classes": [{"value": 1, "name": "a", "color": [1,2,3]}]})")),
      "good.tif", "has class value 2, which the palette");

  // A georeferenced raster on a DEM without georeferencing, and the reverse.
  auto plainDem = openDem(writeSmallDem(dir, false));
  auto onPlain = readMaterialRaster(good, *plainDem);
  expectError(onPlain, "good.tif", "the DEM dem_plain.tif has no georeferencing");
  const std::string plain = dir.file("plain.tif");
  writeRaster(
      plain, 20, 20, GDT_Byte, [](int, int) { return 1; }, {}, 0);
  expectError(read(plain), "plain.tif", "has no georeferencing");
}

}  // namespace
}  // namespace terralod
