#include "terralod/materials/classify_image.h"

#include <cpl_string.h>
#include <cpl_vsi.h>
#include <gdal.h>
#include <gdal_alg.h>

#include <atomic>
#include <filesystem>
#include <memory>
#include <span>

#include "gdal_support.h"
#include "terralod/core/atomic_file.h"

namespace terralod {
namespace {

constexpr int32_t kImageStripRows = 256;
constexpr uint8_t kMaskedValue = 255;

using gdal::Dataset;

// A /vsimem/ file removed when this goes out of scope.
struct MemoryFile {
  std::string path;
  ~MemoryFile() { VSIUnlink(path.c_str()); }
};

std::string memoryPath() {
  static std::atomic<uint64_t> counter{0};
  return "/vsimem/terralod_classify_" + std::to_string(counter++) + ".tif";
}

}  // namespace

std::vector<Material> defaultImagePalette() {
  return {
      {1, "water", {30, 50, 80}},   {2, "vegetation", {40, 70, 35}}, {3, "soil", {150, 120, 95}},
      {4, "rock", {120, 115, 110}}, {5, "snow", {235, 240, 245}},    {6, "shadow", {25, 25, 30}},
  };
}

Result<ClassifyImageResult> classifyImage(const std::string& imagePath,
                                          const std::vector<Material>& palette,
                                          const std::string& outputPath,
                                          const ClassifyOptions& options) {
  gdal::ensureRegistered();
  gdal::QuietErrors quiet;
  if (palette.empty()) return makeError(imagePath, "the palette has no classes");
  if (palette.size() > 255)
    return makeError(imagePath, "the palette has " + std::to_string(palette.size()) +
                                    " classes; at most 255 are supported");
  std::error_code ec;
  if (imagePath.rfind("/vsi", 0) != 0 && !std::filesystem::exists(imagePath, ec))
    return makeError(imagePath, "no such file");
  Dataset image(
      GDALOpenEx(imagePath.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY, nullptr, nullptr, nullptr));
  if (!image) return makeError(imagePath, "not a raster GDAL can read");
  if (GDALGetRasterCount(image.get()) < 3)
    return makeError(imagePath, "is not a colour image (classify needs 3 bands: red, green, blue)");
  for (int b = 1; b <= 3; ++b) {
    const GDALDataType type = GDALGetRasterDataType(GDALGetRasterBand(image.get(), b));
    if (type != GDT_Byte)
      return makeError(imagePath, std::string("band ") + std::to_string(b) + " is " +
                                      GDALGetDataTypeName(type) +
                                      "; classify reads 8-bit RGB images");
  }
  const int32_t columns = GDALGetRasterXSize(image.get()), rows = GDALGetRasterYSize(image.get());
  GDALRasterBandH maskBand = GDALGetMaskBand(GDALGetRasterBand(image.get(), 1));
  const bool hasMask = (GDALGetMaskFlags(GDALGetRasterBand(image.get(), 1)) & GMF_ALL_VALID) == 0;
  if (hasMask)
    for (const Material& m : palette)
      if (m.id == kMaskedValue)
        return makeError(imagePath,
                         "has masked (nodata) pixels, written as 255, but the palette uses "
                         "class value 255");

  // Opened first: an output that cannot be written fails before any work.
  auto file = AtomicFile::create(outputPath);
  if (!file) return file.error();
  // Classified into memory (the sieve reads and rewrites it), then copied into a GeoTIFF.
  GDALDriverH gtiff = GDALGetDriverByName("GTiff");
  GDALDriverH mem = GDALGetDriverByName("MEM");
  if (!gtiff || !mem) return makeError(outputPath, "GDAL has no GeoTIFF or MEM driver");
  Dataset out(GDALCreate(mem, "", columns, rows, 1, GDT_Byte, nullptr));
  if (!out) return makeError(outputPath, "cannot create: " + gdal::lastErrorMessage());
  double gt[6];
  if (GDALGetGeoTransform(image.get(), gt) == CE_None) GDALSetGeoTransform(out.get(), gt);
  if (const char* wkt = GDALGetProjectionRef(image.get()); wkt && *wkt)
    GDALSetProjection(out.get(), wkt);
  GDALRasterBandH band = GDALGetRasterBand(out.get(), 1);
  GDALColorTableH table = GDALCreateColorTable(GPI_RGB);
  for (const Material& m : palette) {
    const GDALColorEntry e{short(m.color[0]), short(m.color[1]), short(m.color[2]), 255};
    GDALSetColorEntry(table, m.id, &e);
  }
  GDALSetRasterColorTable(band, table);
  GDALDestroyColorTable(table);
  GDALSetRasterColorInterpretation(band, GCI_PaletteIndex);
  for (const Material& m : palette)
    GDALSetMetadataItem(band, ("CLASS_NAME_" + std::to_string(m.id)).c_str(), m.name.c_str(),
                        nullptr);
  if (hasMask) GDALSetRasterNoDataValue(band, kMaskedValue);

  ClassifyImageResult result;
  result.columns = columns;
  result.rows = rows;
  result.counts.assign(palette.size(), 0);
  std::vector<uint8_t> rgb(size_t(columns) * kImageStripRows * 3),
      mask(size_t(columns) * kImageStripRows), classes(size_t(columns) * kImageStripRows);
  // Nearest class per colour, computed once for every colour that occurs (a 16 MB table, only
  // the pages of colours that occur are touched).
  std::vector<uint8_t> nearestOf(size_t(1) << 24, 0xff);
  int bands[3] = {1, 2, 3};
  for (int32_t row0 = 0; row0 < rows; row0 += kImageStripRows) {
    const int32_t h = std::min(kImageStripRows, rows - row0);
    if (GDALDatasetRasterIO(image.get(), GF_Read, 0, row0, columns, h, rgb.data(), columns, h,
                            GDT_Byte, 3, bands, 3, int64_t(columns) * 3, 1) != CE_None ||
        GDALRasterIO(maskBand, GF_Read, 0, row0, columns, h, mask.data(), columns, h, GDT_Byte, 0,
                     0) != CE_None)
      return makeError(imagePath, "read failed: " + gdal::lastErrorMessage());
    for (size_t i = 0; i < size_t(columns) * size_t(h); ++i) {
      if (!mask[i]) {
        classes[i] = kMaskedValue;
        ++result.masked;
        continue;
      }
      const uint8_t* p = rgb.data() + i * 3;
      const uint32_t key = (uint32_t(p[0]) << 16) | (uint32_t(p[1]) << 8) | p[2];
      uint8_t& nearest = nearestOf[key];
      if (nearest == 0xff) {
        int best = 0, bestDistance = INT32_MAX;
        for (size_t k = 0; k < palette.size(); ++k) {
          const int dr = int(p[0]) - palette[k].color[0], dg = int(p[1]) - palette[k].color[1],
                    db = int(p[2]) - palette[k].color[2];
          const int distance = dr * dr + dg * dg + db * db;
          if (distance < bestDistance) best = int(k), bestDistance = distance;
        }
        nearest = uint8_t(best);
      }
      classes[i] = palette[nearest].id;
    }
    if (GDALRasterIO(band, GF_Write, 0, row0, columns, h, classes.data(), columns, h, GDT_Byte, 0,
                     0) != CE_None)
      return makeError(outputPath, "write failed: " + gdal::lastErrorMessage());
  }
  if (options.sievePixels > 1 &&
      GDALSieveFilter(band, hasMask ? GDALGetMaskBand(band) : nullptr, band, options.sievePixels, 8,
                      nullptr, nullptr, nullptr) != CE_None)
    return makeError(imagePath, "sieve failed: " + gdal::lastErrorMessage());

  // Counted after the sieve: what the file holds.
  std::vector<int> indexOf(256, -1);
  for (size_t k = 0; k < palette.size(); ++k) indexOf[palette[k].id] = int(k);
  for (int32_t row0 = 0; row0 < rows; row0 += kImageStripRows) {
    const int32_t h = std::min(kImageStripRows, rows - row0);
    if (GDALRasterIO(band, GF_Read, 0, row0, columns, h, classes.data(), columns, h, GDT_Byte, 0,
                     0) != CE_None)
      return makeError(outputPath, "reading the classes back failed: " + gdal::lastErrorMessage());
    for (size_t i = 0; i < size_t(columns) * size_t(h); ++i)
      if (const int k = indexOf[classes[i]]; k >= 0 && !(hasMask && classes[i] == kMaskedValue))
        ++result.counts[size_t(k)];
  }

  MemoryFile memory{memoryPath()};
  CPLStringList createOptions;
  createOptions.SetNameValue("COMPRESS", "DEFLATE");
  createOptions.SetNameValue("ZLEVEL", "9");
  createOptions.SetNameValue("TILED", "YES");
  CPLErrorReset();
  Dataset copy(GDALCreateCopy(gtiff, memory.path.c_str(), out.get(), FALSE, createOptions.List(),
                              nullptr, nullptr));
  if (!copy) return makeError(outputPath, "cannot create: " + gdal::lastErrorMessage());
  GDALClose(copy.release());  // flushes the compressed tiles
  if (CPLGetLastErrorType() == CE_Failure)
    return makeError(outputPath, "write failed: " + gdal::lastErrorMessage());

  vsi_l_offset size = 0;
  const GByte* bytes = VSIGetMemFileBuffer(memory.path.c_str(), &size, FALSE);
  if (!bytes) return makeError(outputPath, "write failed: the GeoTIFF was not produced");
  if (Status s = file->write(std::span<const uint8_t>(bytes, size_t(size))); !s) return s.error();
  if (Status s = file->commit(); !s) return s.error();
  return result;
}

}  // namespace terralod
