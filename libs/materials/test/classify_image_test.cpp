#include "terralod/materials/classify_image.h"

#include <gdal.h>
#include <gdal_priv.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>

#include "temp_dir.h"
#include "terralod/materials/material_raster.h"
#include "terralod/materials/palette.h"

namespace terralod {
namespace {

const std::string kImage = test::testData("zion_landsat8_rgb_utm12_30m.tif");
const std::string kPalette = test::testData("zion_landcover_palette.json");

std::vector<uint8_t> readBands(const std::string& path, int bands) {
  GDALDatasetH ds = GDALOpen(path.c_str(), GA_ReadOnly);
  EXPECT_NE(ds, nullptr) << path;
  const int w = GDALGetRasterXSize(ds), h = GDALGetRasterYSize(ds);
  std::vector<uint8_t> out(size_t(w) * h * bands);
  std::vector<int> list;
  for (int b = 1; b <= bands; ++b) list.push_back(b);
  EXPECT_EQ(GDALDatasetRasterIO(ds, GF_Read, 0, 0, w, h, out.data(), w, h, GDT_Byte, bands,
                                list.data(), bands, int64_t(w) * bands, 1),
            CE_None);
  GDALClose(ds);
  return out;
}

TEST(ClassifyImage, NearestPaletteColourWithGeoreferencingColourTableAndNames) {
  GDALAllRegister();
  test::TempDir dir;
  auto palette = readPalette(kPalette);
  ASSERT_TRUE(palette.ok()) << palette.error().message;
  const std::string out = dir.file("classes.tif");
  auto result = classifyImage(kImage, *palette, out);
  ASSERT_TRUE(result.ok()) << result.error().message;
  EXPECT_EQ(result->columns, 1128);
  EXPECT_EQ(result->rows, 1428);
  uint64_t total = 0;
  for (uint64_t c : result->counts) total += c;
  EXPECT_EQ(total, 1128u * 1428u);

  const std::vector<uint8_t> rgb = readBands(kImage, 3), classes = readBands(out, 1);
  for (size_t i = 0; i < classes.size(); i += 997) {
    int best = 0, bestD = INT32_MAX;
    for (size_t k = 0; k < palette->size(); ++k) {
      int d = 0;
      for (int c = 0; c < 3; ++c) {
        const int e = int(rgb[i * 3 + c]) - (*palette)[k].color[c];
        d += e * e;
      }
      if (d < bestD) best = int(k), bestD = d;
    }
    ASSERT_EQ(classes[i], (*palette)[size_t(best)].id) << "pixel " << i;
  }

  GDALDatasetH ds = GDALOpen(out.c_str(), GA_ReadOnly);
  ASSERT_EQ(GDALGetRasterCount(ds), 1);
  GDALRasterBandH band = GDALGetRasterBand(ds, 1);
  EXPECT_EQ(GDALGetRasterDataType(band), GDT_Byte);
  EXPECT_STREQ(GDALGetMetadataItem(ds, "COMPRESSION", "IMAGE_STRUCTURE"), "DEFLATE");
  double gt[6];
  ASSERT_EQ(GDALGetGeoTransform(ds, gt), CE_None);
  EXPECT_EQ(gt[0], 301905.0);
  EXPECT_EQ(gt[3], 4154085.0);
  EXPECT_NE(std::string(GDALGetProjectionRef(ds)).find("UTM zone 12N"), std::string::npos);
  GDALColorTableH table = GDALGetRasterColorTable(band);
  ASSERT_NE(table, nullptr);
  const GDALColorEntry* e = GDALGetColorEntry(table, 2);
  EXPECT_EQ(e->c1, 170);
  EXPECT_EQ(e->c2, 120);
  EXPECT_EQ(e->c3, 105);
  EXPECT_STREQ(GDALGetMetadataItem(band, "CLASS_NAME_3", nullptr), "pale sandstone");
  GDALClose(ds);
  EXPECT_FALSE(std::filesystem::exists(out + ".aux.xml"));  // everything inside the TIFF

  // The committed tests/data file is exactly what the command makes from the committed inputs.
  EXPECT_EQ(readBands(test::testData("zion_landcover_classes.tif"), 1), classes);
}

// Sizes of the 8-connected regions of equal values in a w x h raster.
std::vector<size_t> regionSizes(const std::vector<uint8_t>& v, int w, int h) {
  std::vector<uint8_t> seen(v.size(), 0);
  std::vector<size_t> sizes, stack;
  for (size_t start = 0; start < v.size(); ++start) {
    if (seen[start]) continue;
    size_t size = 0;
    seen[start] = 1;
    stack.push_back(start);
    while (!stack.empty()) {
      const size_t i = stack.back();
      stack.pop_back();
      ++size;
      const int x = int(i % size_t(w)), y = int(i / size_t(w));
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const int nx = x + dx, ny = y + dy;
          if (nx < 0 || ny < 0 || nx >= w || ny >= h) continue;
          const size_t j = size_t(ny) * size_t(w) + size_t(nx);
          if (!seen[j] && v[j] == v[start]) {
            seen[j] = 1;
            stack.push_back(j);
          }
        }
    }
    sizes.push_back(size);
  }
  return sizes;
}

TEST(ClassifyImage, TheSieveLeavesNoRegionSmallerThanItsThreshold) {
  test::TempDir dir;
  auto palette = readPalette(kPalette);
  ASSERT_TRUE(palette.ok()) << palette.error().message;
  ClassifyOptions options;
  options.sievePixels = 16;
  auto sieved = classifyImage(kImage, *palette, dir.file("sieved.tif"), options);
  ASSERT_TRUE(sieved.ok()) << sieved.error().message;
  auto raw = classifyImage(kImage, *palette, dir.file("raw.tif"));
  ASSERT_TRUE(raw.ok()) << raw.error().message;
  auto small = [](const std::vector<size_t>& sizes) {
    return std::count_if(sizes.begin(), sizes.end(), [](size_t n) { return n < 16; });
  };
  // Per-pixel classes are speckled; the sieve merges every speck into a neighbour.
  EXPECT_GT(small(regionSizes(readBands(dir.file("raw.tif"), 1), 1128, 1428)), 1000);
  const std::vector<uint8_t> classes = readBands(dir.file("sieved.tif"), 1);
  EXPECT_EQ(small(regionSizes(classes, 1128, 1428)), 0);
  // The counts are the file's.
  for (size_t k = 0; k < palette->size(); ++k)
    EXPECT_EQ(sieved->counts[k],
              uint64_t(std::count(classes.begin(), classes.end(), (*palette)[k].id)))
        << k;
}

TEST(ClassifyImage, BadInputWritesNothing) {
  test::TempDir dir;
  const std::string out = dir.file("out.tif");
  const auto palette = defaultImagePalette();
  auto missing = classifyImage(dir.file("nope.tif"), palette, out);
  ASSERT_FALSE(missing.ok());
  EXPECT_NE(missing.error().message.find("nope.tif: no such file"), std::string::npos);
  // A one-band raster is not a colour image.
  auto gray = classifyImage(test::testData("zion_srtm3_utm12_30m.tif"), palette, out);
  ASSERT_FALSE(gray.ok());
  EXPECT_NE(gray.error().message.find("is not a colour image"), std::string::npos)
      << gray.error().message;
  EXPECT_FALSE(std::filesystem::exists(out));
  // An existing output stays as it was when the command fails.
  std::ofstream(out) << "old";
  ASSERT_FALSE(classifyImage(test::testData("zion_srtm3_utm12_30m.tif"), palette, out).ok());
  std::ifstream in(out);
  std::string text;
  in >> text;
  EXPECT_EQ(text, "old");
  auto noDir = classifyImage(kImage, palette, dir.file("missing/out.tif"));
  ASSERT_FALSE(noDir.ok());
  EXPECT_NE(noDir.error().message.find("missing/out.tif"), std::string::npos);
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir.path()), {}), 1);
}

}  // namespace
}  // namespace terralod
