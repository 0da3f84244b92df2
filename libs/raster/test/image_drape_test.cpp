#include "terralod/raster/image_drape.h"

#include <gdal_priv.h>
#include <gtest/gtest.h>
#include <ogr_spatialref.h>

#include <cmath>
#include <fstream>
#include <functional>
#include <random>

#include "temp_dir.h"

namespace terralod {
namespace {

using test::TempDir;
using test::testData;

const std::string kDemUtm = "zion_srtm3_utm12_30m.tif";          // UTM 12N, 30 m, 1128 x 1428
const std::string kDemGeo = "zion_srtm3.tif";                    // EPSG:4326, 3", 465 x 457
const std::string kLandsat = "zion_landsat8_rgb_utm12_30m.tif";  // RGB on kDemUtm's grid

DemInfo demInfo(const std::string& name) {
  auto r = DemReader::open(testData(name), {});
  EXPECT_TRUE(r.ok()) << (r ? "" : r.error().message);
  return r ? (*r)->info() : DemInfo{};
}

std::unique_ptr<ImageDrape> drape(const std::string& image, const DemInfo& dem) {
  auto r = ImageDrape::open(image, dem);
  EXPECT_TRUE(r.ok()) << (r ? "" : r.error().message);
  return r ? std::move(r).value() : nullptr;
}

std::string openError(const std::string& image, const DemInfo& dem) {
  auto r = ImageDrape::open(image, dem);
  return r ? "(opened without error)" : r.error().message;
}

// An image's RGB bands as GDAL reads them, raster rows from the top.
struct Rgb8 {
  int columns = 0, rows = 0;
  std::vector<uint8_t> rgb;  // pixel-interleaved
  int at(int column, int row, int band) const {
    return rgb[(size_t(row) * columns + column) * 3 + size_t(band)];
  }
};

Rgb8 readImage(const std::string& path) {
  GDALAllRegister();
  GDALDatasetUniquePtr ds(GDALDataset::Open(path.c_str(), GDAL_OF_RASTER));
  Rgb8 img;
  if (!ds) {
    ADD_FAILURE() << "cannot open " << path;
    return img;
  }
  img.columns = ds->GetRasterXSize();
  img.rows = ds->GetRasterYSize();
  img.rgb.resize(size_t(img.columns) * img.rows * 3);
  int bands[3] = {1, 2, 3};
  EXPECT_EQ(ds->RasterIO(GF_Read, 0, 0, img.columns, img.rows, img.rgb.data(), img.columns,
                         img.rows, GDT_Byte, 3, bands, 3, int64_t(img.columns) * 3, 1, nullptr),
            CE_None);
  return img;
}

std::vector<uint8_t> readDrape(const ImageDrape& d, int64_t x0, int64_t y0, int32_t w, int32_t h) {
  std::vector<uint8_t> rgba(size_t(w) * h * 4, 0xCD);
  const Status s = d.read(x0, y0, w, h, rgba.data());
  EXPECT_TRUE(s.ok()) << (s ? "" : s.error().message);
  return rgba;
}

// A small GeoTIFF: `gt` empty for none, `epsg` 0 for no CRS; band b's pixel (column, row) is
// value(b, column, row); `alphaLast` marks the last band as alpha.
void writeImage(const std::string& path, int columns, int rows, int bands, std::vector<double> gt,
                int epsg, GDALDataType type = GDT_Byte,
                std::function<double(int, int, int)> value = {}, bool alphaLast = false) {
  GDALAllRegister();
  GDALDriver* driver = GetGDALDriverManager()->GetDriverByName("GTiff");
  GDALDataset* ds = driver->Create(path.c_str(), columns, rows, bands, type, nullptr);
  ASSERT_NE(ds, nullptr);
  if (!gt.empty()) ds->SetGeoTransform(gt.data());
  if (epsg != 0) {
    OGRSpatialReference srs;
    srs.importFromEPSG(epsg);
    ds->SetSpatialRef(&srs);
  }
  if (!value) value = [](int b, int c, int r) { return double(((r * 16 + c) * 7 + b * 50) % 256); };
  std::vector<double> pixels(size_t(columns) * rows);
  for (int b = 1; b <= bands; ++b) {
    for (int r = 0; r < rows; ++r)
      for (int c = 0; c < columns; ++c) pixels[size_t(r) * columns + c] = value(b, c, r);
    EXPECT_EQ(ds->GetRasterBand(b)->RasterIO(GF_Write, 0, 0, columns, rows, pixels.data(), columns,
                                             rows, GDT_Float64, 0, 0),
              CE_None);
  }
  if (alphaLast) ds->GetRasterBand(bands)->SetColorInterpretation(GCI_AlphaBand);
  GDALClose(ds);
}

TEST(ImageDrape, SameGridImageLandsOnItsOwnSamples) {
  const DemInfo dem = demInfo(kDemUtm);
  ASSERT_EQ(dem.columns, 1128);
  ASSERT_EQ(dem.rows, 1428);
  auto d = drape(testData(kLandsat), dem);
  ASSERT_TRUE(d);
  EXPECT_EQ(d->refine(), 1u);
  EXPECT_NEAR(d->coverage(), 1.0, 1e-6);
  EXPECT_EQ(d->path(), testData(kLandsat));

  const Rgb8 img = readImage(testData(kLandsat));
  ASSERT_EQ(img.columns, dem.columns);
  ASSERT_EQ(img.rows, dem.rows);
  // Windows in the middle and at the corners; grid row gy is raster row rows - 1 - gy.
  for (auto [x0, y0, w, h] : {std::tuple{500, 600, 48, 33}, std::tuple{0, 0, 20, 17},
                              std::tuple{1128 - 25, 1428 - 19, 25, 19}}) {
    const std::vector<uint8_t> rgba = readDrape(*d, x0, y0, w, h);
    int different = 0;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const uint8_t* p = &rgba[(size_t(y) * w + x) * 4];
        const int column = x0 + x, row = dem.rows - 1 - (y0 + y);
        for (int c = 0; c < 3; ++c) different += p[c] != img.at(column, row, c);
        EXPECT_EQ(int(p[3]), 255) << column << "," << row;
      }
    EXPECT_EQ(different, 0) << "window at " << x0 << "," << y0;
  }
  // The window read is not flipped: a texel with a different colour from its northern
  // neighbour in the image keeps that difference in the right direction.
  const std::vector<uint8_t> strip = readDrape(*d, 700, 300, 1, 200);
  int changes = 0;
  for (int y = 0; y + 1 < 200; ++y) changes += strip[size_t(y) * 4] != strip[size_t(y + 1) * 4];
  EXPECT_GT(changes, 50);  // the image has detail there, so the comparison above means something
}

TEST(ImageDrape, WindowsOutsideTheGridRepeatTheNearestTexel) {
  const DemInfo dem = demInfo(kDemUtm);
  auto d = drape(testData(kLandsat), dem);
  ASSERT_TRUE(d);
  const int64_t W = dem.columns, H = dem.rows;
  for (auto [x0, y0] :
       {std::pair<int64_t, int64_t>{-4, -3}, std::pair<int64_t, int64_t>{W - 3, H - 2}}) {
    const int32_t w = 9, h = 7;
    const std::vector<uint8_t> rgba = readDrape(*d, x0, y0, w, h);
    const int64_t cx0 = std::clamp<int64_t>(x0, 0, W - 1), cy0 = std::clamp<int64_t>(y0, 0, H - 1);
    const int64_t cx1 = std::clamp<int64_t>(x0 + w - 1, 0, W - 1),
                  cy1 = std::clamp<int64_t>(y0 + h - 1, 0, H - 1);
    const std::vector<uint8_t> inside =
        readDrape(*d, cx0, cy0, int32_t(cx1 - cx0 + 1), int32_t(cy1 - cy0 + 1));
    for (int32_t y = 0; y < h; ++y)
      for (int32_t x = 0; x < w; ++x) {
        const int64_t gx = std::clamp<int64_t>(x0 + x, 0, W - 1) - cx0,
                      gy = std::clamp<int64_t>(y0 + y, 0, H - 1) - cy0;
        for (int c = 0; c < 4; ++c)
          ASSERT_EQ(rgba[(size_t(y) * w + x) * 4 + c],
                    inside[(size_t(gy) * (cx1 - cx0 + 1) + gx) * 4 + c])
              << x0 + x << "," << y0 + y;
      }
  }
}

TEST(ImageDrape, ReopenReadsTheSame) {
  const DemInfo dem = demInfo(kDemUtm);
  auto d = drape(testData(kLandsat), dem);
  ASSERT_TRUE(d);
  auto again = d->reopen();
  ASSERT_TRUE(again.ok()) << again.error().message;
  EXPECT_EQ((*again)->refine(), d->refine());
  EXPECT_EQ((*again)->coverage(), d->coverage());
  EXPECT_EQ(readDrape(**again, 300, 900, 31, 17), readDrape(*d, 300, 900, 31, 17));
}

// The UTM image over the same area's geographic DEM: reprojected by the warper, refined
// twice (3" cells of ~74 x 93 m against 30 m pixels). Each fine texel should show the image
// where its grid point's longitude and latitude fall in UTM.
class GeographicDrape : public testing::Test {
 protected:
  void SetUp() override {
    dem = demInfo(kDemGeo);
    image = readImage(testData(kLandsat));
    GDALAllRegister();
    GDALDatasetUniquePtr ds(GDALDataset::Open(testData(kLandsat).c_str(), GDAL_OF_RASTER));
    ASSERT_TRUE(ds);
    ASSERT_EQ(ds->GetGeoTransform(imageGt), CE_None);
    OGRSpatialReference geo, utm;
    ASSERT_EQ(geo.importFromWkt(dem.crsWkt.c_str()), OGRERR_NONE);
    ASSERT_EQ(utm.importFromEPSG(32612), OGRERR_NONE);
    geo.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
    utm.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
    toUtm.reset(OGRCreateCoordinateTransformation(&geo, &utm));
    ASSERT_TRUE(toUtm);
  }

  // The image's pixel coordinates (column, row; pixel centres at .5) of fine texel (fx, fy).
  std::pair<double, double> imagePixel(double fx, double fy, uint32_t refine) const {
    const auto& g = dem.geoTransform;
    const double gx = fx / refine, gy = fy / refine;
    double x = g[0] + (gx + 0.5) * g[1], y = g[3] + (dem.rows - 1 - gy + 0.5) * g[5];
    EXPECT_TRUE(toUtm->Transform(1, &x, &y));
    return {(x - imageGt[0]) / imageGt[1], (y - imageGt[3]) / imageGt[5]};
  }

  // The image bilinearly interpolated at pixel coordinates (u, v).
  double bilinear(double u, double v, int band) const {
    const double x = u - 0.5, y = v - 0.5;
    const int ix = int(std::floor(x)), iy = int(std::floor(y));
    const double tx = x - ix, ty = y - iy;
    auto at = [&](int c, int r) {
      return double(
          image.at(std::clamp(c, 0, image.columns - 1), std::clamp(r, 0, image.rows - 1), band));
    };
    return (1 - ty) * ((1 - tx) * at(ix, iy) + tx * at(ix + 1, iy)) +
           ty * ((1 - tx) * at(ix, iy + 1) + tx * at(ix + 1, iy + 1));
  }

  // Mean colour of the image over the w x h fine texels from (fx0, fy0), each texel shifted
  // by (sx, sy) fine texels.
  std::array<double, 3> expectedMean(int64_t fx0, int64_t fy0, int w, int h, uint32_t refine,
                                     double sx = 0, double sy = 0) const {
    std::array<double, 3> sum{};
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const auto [u, v] = imagePixel(double(fx0 + x) + sx, double(fy0 + y) + sy, refine);
        for (int c = 0; c < 3; ++c) sum[size_t(c)] += bilinear(u, v, c);
      }
    for (double& s : sum) s /= w * h;
    return sum;
  }

  DemInfo dem;
  Rgb8 image;
  double imageGt[6] = {};
  std::unique_ptr<OGRCoordinateTransformation> toUtm;
};

TEST_F(GeographicDrape, ColoursMatchTheImageAtTheSamplesLonLat) {
  ASSERT_EQ(dem.columns, 465);
  ASSERT_EQ(dem.rows, 457);
  auto d = drape(testData(kLandsat), dem);
  ASSERT_TRUE(d);
  EXPECT_EQ(d->refine(), 2u);
  // The UTM image covers the geographic DEM but for slivers along its edges.
  EXPECT_GT(d->coverage(), 0.95);
  EXPECT_LE(d->coverage(), 1.0);
  const uint32_t r = d->refine();

  // Windows of 9 x 9 fine texels (~370 m) well inside: their mean colour against the image's
  // mean over the same points. Averaging evens out the warper's own resampling (GDAL picks
  // "average" here, the image's pixels being finer than the fine grid's); the tolerance is
  // checked to be meaningful: windows displaced by two fine texels (~80 m) fail it.
  const int w = 9;
  const double tolerance = 3.0;
  int discriminating = 0, windows = 0;
  for (int64_t gy = 40; gy < dem.rows - 40; gy += 47)
    for (int64_t gx = 40; gx < dem.columns - 40; gx += 53) {
      const int64_t fx0 = gx * r, fy0 = gy * r;
      const std::vector<uint8_t> rgba = readDrape(*d, fx0, fy0, w, w);
      std::array<double, 3> mean{};
      for (int i = 0; i < w * w; ++i) {
        for (int c = 0; c < 3; ++c) mean[size_t(c)] += rgba[size_t(i) * 4 + c];
        ASSERT_EQ(int(rgba[size_t(i) * 4 + 3]), 255);
      }
      for (double& m : mean) m /= w * w;
      const auto expected = expectedMean(fx0, fy0, w, w, r);
      double worstShifted = 0;
      for (auto [sx, sy] :
           {std::pair{2.0, 0.0}, std::pair{-2.0, 0.0}, std::pair{0.0, 2.0}, std::pair{0.0, -2.0}}) {
        const auto shifted = expectedMean(fx0, fy0, w, w, r, sx, sy);
        for (int c = 0; c < 3; ++c)
          worstShifted = std::max(worstShifted, std::abs(shifted[size_t(c)] - mean[size_t(c)]));
      }
      ++windows;
      discriminating += worstShifted > tolerance;
      for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(mean[size_t(c)], expected[size_t(c)], tolerance)
            << "window at grid " << gx << "," << gy << " band " << c;
    }
  EXPECT_GE(windows, 50);
  EXPECT_GE(discriminating, windows * 3 / 4);
}

// Single texels: the warper resamples the image over each fine texel's footprint (~37 x 46 m,
// against 30 m pixels), so a texel's colour lies within the range of the image's 3 x 3 pixels
// around the point its grid point's lon/lat falls on (+-1 for rounding). Every texel of a
// large window passes; the same check with the points displaced by one fine texel (~40 m)
// fails for many, so it does tell placements apart.
TEST_F(GeographicDrape, EveryTexelWithinTheImagesLocalRange) {
  auto d = drape(testData(kLandsat), dem);
  ASSERT_TRUE(d);
  const uint32_t r = d->refine();
  const int64_t fx0 = 250, fy0 = 300;
  const int32_t w = 240, h = 200;
  const std::vector<uint8_t> rgba = readDrape(*d, fx0, fy0, w, h);
  auto outside = [&](double sx, double sy) {
    int64_t count = 0;
    for (int32_t y = 0; y < h; ++y)
      for (int32_t x = 0; x < w; ++x) {
        const auto [u, v] = imagePixel(double(fx0 + x) + sx, double(fy0 + y) + sy, r);
        const uint8_t* p = &rgba[(size_t(y) * w + x) * 4];
        bool out = false;
        for (int c = 0; c < 3; ++c) {
          int lo = 255, hi = 0;
          for (int j = -1; j <= 1; ++j)
            for (int i = -1; i <= 1; ++i) {
              const int q = image.at(int(u) + i, int(v) + j, c);
              lo = std::min(lo, q);
              hi = std::max(hi, q);
            }
          out |= p[c] < lo - 1 || p[c] > hi + 1;
        }
        count += out;
      }
    return count;
  };
  EXPECT_EQ(outside(0, 0), 0);
  for (auto [sx, sy] :
       {std::pair{1.0, 0.0}, std::pair{-1.0, 0.0}, std::pair{0.0, 1.0}, std::pair{0.0, -1.0}})
    EXPECT_GT(outside(sx, sy), int64_t(w) * h / 20) << "displaced by " << sx << "," << sy;
}

// Neighbouring blocks read overlapping windows (their shared border texels, margins): a
// texel's value must not depend on the window it is read with, or the draped colour would
// seam at block borders.
TEST_F(GeographicDrape, TexelsDoNotDependOnTheWindowRead) {
  auto d = drape(testData(kLandsat), dem);
  ASSERT_TRUE(d);
  const int32_t n = 129;
  const int64_t x0 = 100, y0 = 150;
  const std::vector<uint8_t> a = readDrape(*d, x0, y0, n, n);
  for (auto [dx, dy, w, h] : {std::tuple{n - 1, 0, n, n}, std::tuple{0, n - 1, n, n},
                              std::tuple{7, 3, 65, 200}, std::tuple{-30, 40, 300, 17}}) {
    const std::vector<uint8_t> b = readDrape(*d, x0 + dx, y0 + dy, w, h);
    int64_t compared = 0;
    for (int32_t y = 0; y < h; ++y)
      for (int32_t x = 0; x < w; ++x) {
        const int64_t ax = dx + x, ay = dy + y;  // in a's window
        if (ax < 0 || ay < 0 || ax >= n || ay >= n) continue;
        ++compared;
        for (int c = 0; c < 4; ++c)
          ASSERT_EQ(b[(size_t(y) * w + x) * 4 + c], a[(size_t(ay) * n + ax) * 4 + c])
              << "window " << dx << "," << dy << " texel " << ax << "," << ay;
      }
    EXPECT_GT(compared, 100);
  }
}

TEST(ImageDrape, ImageThatDoesNotOverlapTheDem) {
  TempDir dir;
  const std::string path = dir.file("far_away.tif");
  // UTM 12N, 200 km south of the DEM.
  writeImage(path, 16, 16, 3, {301905, 30, 0, 3954085, 0, -30}, 32612);
  EXPECT_EQ(openError(path, demInfo(kDemUtm)),
            path + ": does not overlap the DEM zion_srtm3_utm12_30m.tif");
  // Touching the DEM's western edge from outside is no overlap either.
  const std::string touching = dir.file("touching.tif");
  writeImage(touching, 16, 16, 3, {301905 - 16 * 30, 30, 0, 4154085, 0, -30}, 32612);
  EXPECT_EQ(openError(touching, demInfo(kDemUtm)),
            touching + ": does not overlap the DEM zion_srtm3_utm12_30m.tif");
}

TEST(ImageDrape, CorruptImageFile) {
  TempDir dir;
  const std::string path = dir.file("noise.tif");
  {
    std::mt19937 rng(8);
    std::ofstream out(path, std::ios::binary);
    for (int i = 0; i < 4096; ++i) out.put(char(rng()));
  }
  const std::string message = openError(path, demInfo(kDemUtm));
  // GDAL records no reason when no driver recognises the file; the message says so.
  EXPECT_EQ(message, path + ": cannot be read as an image (not a raster format GDAL knows)");
}

TEST(ImageDrape, TruncatedGeoTiff) {
  TempDir dir;
  const std::string path = dir.file("cut.tif");
  {
    std::ifstream in(testData(kLandsat), std::ios::binary);
    std::vector<char> bytes(2000);
    in.read(bytes.data(), std::streamsize(bytes.size()));
    std::ofstream out(path, std::ios::binary);
    out.write(bytes.data(), std::streamsize(bytes.size()));
  }
  const std::string message = openError(path, demInfo(kDemUtm));
  // The reason is libtiff's (e.g. "TIFFReadDirectory:IO error during reading of ..."), so
  // only its start is fixed here.
  const std::string start = path + ": cannot be read as an image: ";
  EXPECT_EQ(message.rfind(start, 0), 0u) << message;
  EXPECT_GT(message.size(), start.size()) << message;
}

TEST(ImageDrape, ImageWithoutGeoreferencing) {
  TempDir dir;
  const std::string path = dir.file("plain.tif");
  writeImage(path, 16, 16, 3, {}, 0);
  EXPECT_EQ(openError(path, demInfo(kDemUtm)),
            path + ": has no georeferencing, so it cannot be placed on the DEM");
  // A geotransform but no coordinate system, over a DEM that has one.
  const std::string noCrs = dir.file("no_crs.tif");
  writeImage(noCrs, 16, 16, 3, {310000, 30, 0, 4130000, 0, -30}, 0);
  EXPECT_EQ(openError(noCrs, demInfo(kDemUtm)),
            noCrs + ": has no coordinate system (the DEM has one)");
}

// A 40 x 40 image inside the UTM DEM, on its grid: image pixel (c, r) is DEM grid point
// (c + 270, 1427 - (r + 802)).
constexpr int kPatchColumn = 270, kPatchRow = 802;
const std::vector<double> kPatchGt = {301905 + kPatchColumn * 30.0, 30, 0,
                                      4154085 - kPatchRow * 30.0,   0,  -30};

TEST(ImageDrape, GreyWideImageIsStretchedToBytes) {
  TempDir dir;
  const std::string path = dir.file("grey16.tif");
  // UInt16 1000 .. 1975 across the columns: stretched to 0 .. 255 on all three channels.
  writeImage(path, 40, 40, 1, kPatchGt, 32612, GDT_UInt16,
             [](int, int c, int) { return 1000.0 + 25 * c; });
  const DemInfo dem = demInfo(kDemUtm);
  auto d = drape(path, dem);
  ASSERT_TRUE(d);
  EXPECT_EQ(d->refine(), 1u);
  EXPECT_NEAR(d->coverage(), 40.0 * 40 / (1128.0 * 1428), 1e-9);
  const int64_t gy = dem.rows - 1 - (kPatchRow + 5);
  const std::vector<uint8_t> rgba = readDrape(*d, kPatchColumn - 2, gy, 44, 1);
  for (int x = 0; x < 44; ++x) {
    const uint8_t* p = &rgba[size_t(x) * 4];
    const int c = x - 2;
    if (c < 0 || c >= 40) {
      EXPECT_EQ(int(p[3]), 0) << x;  // no image there
      continue;
    }
    EXPECT_EQ(int(p[3]), 255) << x;
    for (int ch = 0; ch < 3; ++ch) EXPECT_EQ(int(p[ch]), std::lround(c * 255.0 / 39)) << x;
  }
}

TEST(ImageDrape, AlphaBandMakesTexelsTransparent) {
  TempDir dir;
  const std::string path = dir.file("rgba.tif");
  // Opaque in the western half, transparent in the eastern.
  writeImage(
      path, 40, 40, 4, kPatchGt, 32612, GDT_Byte,
      [](int b, int c, int r) { return b == 4 ? (c < 20 ? 255.0 : 0.0) : 6.0 * c + b + r; }, true);
  const DemInfo dem = demInfo(kDemUtm);
  auto d = drape(path, dem);
  ASSERT_TRUE(d);
  const int64_t gy = dem.rows - 1 - (kPatchRow + 7);
  const std::vector<uint8_t> rgba = readDrape(*d, kPatchColumn, gy, 40, 1);
  for (int c = 0; c < 40; ++c) {
    const uint8_t* p = &rgba[size_t(c) * 4];
    EXPECT_EQ(int(p[3]), c < 20 ? 255 : 0) << c;
    if (c < 20) {
      for (int ch = 0; ch < 3; ++ch) EXPECT_EQ(int(p[ch]), 6 * c + ch + 1 + 7) << c;
    }
  }
}

// A one-band image with a colour table (a paletted GeoTIFF, PNG or GIF: land-cover maps and
// scanned charts often are) shows its palette's colours, or is refused. Fails at the time of
// writing: the palette indices are drawn as grey levels (0 and 1 here: black) without error.
TEST(ImageDrape, PalettedImageShowsItsColoursOrIsRefused) {
  TempDir dir;
  const std::string path = dir.file("paletted.tif");
  writeImage(path, 40, 40, 1, kPatchGt, 32612, GDT_Byte,
             [](int, int c, int) { return c < 20 ? 0.0 : 1.0; });
  {
    GDALDatasetUniquePtr ds(GDALDataset::Open(path.c_str(), GDAL_OF_RASTER | GDAL_OF_UPDATE));
    ASSERT_TRUE(ds);
    GDALColorTable table;
    const GDALColorEntry red{255, 0, 0, 255}, blue{0, 0, 255, 255};
    table.SetColorEntry(0, &red);
    table.SetColorEntry(1, &blue);
    ASSERT_EQ(ds->GetRasterBand(1)->SetColorTable(&table), CE_None);
  }
  const DemInfo dem = demInfo(kDemUtm);
  auto r = ImageDrape::open(path, dem);
  if (!r.ok()) {  // refusing it is fine, naming the image
    EXPECT_EQ(r.error().message.rfind(path + ": ", 0), 0u) << r.error().message;
    return;
  }
  const int64_t gy = dem.rows - 1 - (kPatchRow + 8);
  const std::vector<uint8_t> rgba = readDrape(**r, kPatchColumn, gy, 40, 1);
  for (int c : {5, 15, 25, 35}) {
    const uint8_t* p = &rgba[size_t(c) * 4];
    const int expected[3] = {c < 20 ? 255 : 0, 0, c < 20 ? 0 : 255};
    for (int ch = 0; ch < 3; ++ch)
      EXPECT_EQ(int(p[ch]), expected[ch]) << "column " << c << " channel " << ch;
  }
}

TEST(ImageDrape, DemWithoutGeoreferencingOrCrs) {
  TempDir dir;
  const std::string path = dir.file("patch.tif");
  writeImage(path, 40, 40, 3, kPatchGt, 32612);
  DemInfo dem = demInfo(kDemUtm);
  dem.hasGeoTransform = false;
  EXPECT_EQ(openError(path, dem),
            path + ": cannot be placed: the DEM " + kDemUtm + " has no georeferencing");
  dem = demInfo(kDemUtm);
  dem.crsWkt.clear();
  EXPECT_EQ(openError(path, dem), path + ": has a coordinate system but the DEM has none");
}

TEST(ImageDrape, MissingImageFile) {
  TempDir dir;
  const std::string path = dir.file("nothing.tif");
  EXPECT_EQ(openError(path, demInfo(kDemUtm)), path + ": no such file");
}

}  // namespace
}  // namespace terralod
