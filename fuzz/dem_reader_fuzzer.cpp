// Fuzzes the raster loader: DemReader on an in-memory GeoTIFF or PNG (GDAL's /vsimem/), with
// plain heights or terrain-RGB / Terrarium decoding, reading heights as build does (a small
// raster whole, in strips, then its voids filled; a large one by its approximate height range
// and a window, here at one corner, reaching past the edges). Input: one mode byte (bits 0-1:
// plain, terrain-rgb, terrarium, plain from band 1 asked for explicitly, which reads rasters
// of several 8-bit bands that plain alone refuses; bits 2-3: which corner), then the file.
//
// Only GDAL's GTiff and PNG drivers stay registered: the target is terralod's handling of what
// GDAL hands back, not GDAL's other two hundred drivers. GDAL itself is not instrumented here.
//
// Cost per input: a few bytes of header can declare blocks or rasters of gigabytes, which
// GDAL then allocates, zeroes and decodes (not terralod's code, and 10 ms or more an input).
// So the reader is opened with a 1 MB block limit (DemOpenOptions::maxBlockBytes, whose own
// check stays exercised), and the approximate height range, which may decode every block, is
// asked only of rasters up to kRangeSamples; larger ones get the window read.

#include <gdal_priv.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "terralod/raster/dem_reader.h"
#include "terralod/raster/heightfield.h"
#include "terralod/raster/void_fill.h"

namespace {

constexpr const char* kPath = "/vsimem/fuzz_input";
constexpr int64_t kWholeSamples = int64_t{1} << 16;  // small enough for thousands a second
constexpr int64_t kRangeSamples = int64_t{1} << 22;

void readLikeBuild(const terralod::DemReader& reader, int corner) {
  const terralod::DemInfo& info = reader.info();
  if (int64_t(info.columns) * info.rows <= kWholeSamples) {
    terralod::Heightfield heights(info.columns, info.rows);
    for (int32_t y = 0; y < info.rows; y += 256) {
      const int32_t n = std::min(256, info.rows - y);
      if (!reader.readWindow(0, y, info.columns, n, heights.row(y))) return;
    }
    (void)terralod::fillVoids(heights, info.path);
    return;
  }
  if (int64_t(info.columns) * info.rows <= kRangeSamples) (void)reader.approximateHeightRange();
  // One window per input (GDAL may decode a whole strip of hundreds of MB for each).
  constexpr int32_t kSide = 64, kMargin = 8;
  std::vector<float> window(size_t(kSide) * kSide);
  const int32_t x0 = corner & 1 ? info.columns - kSide + kMargin : -kMargin;
  const int32_t y0 = corner & 2 ? info.rows - kSide + kMargin : -kMargin;
  (void)reader.readWindow(x0, y0, kSide, kSide, window.data());
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  // Registers every driver, once. 16 MB of block cache holds any input's 1 MB blocks.
  terralod::setGdalCacheBytes(uint64_t{16} << 20);
  GDALDriverManager* drivers = GetGDALDriverManager();
  for (int i = drivers->GetDriverCount() - 1; i >= 0; --i) {
    GDALDriver* driver = drivers->GetDriver(i);
    const std::string name = driver->GetDescription();
    if (name == "GTiff" || name == "PNG") continue;
    drivers->DeregisterDriver(driver);
    GDALDestroyDriver(driver);
  }
  // No side-car files (.aux.xml, .ovr, world files) to look for in /vsimem/.
  CPLSetConfigOption("GDAL_PAM_ENABLED", "NO");
  CPLSetConfigOption("GDAL_DISABLE_READDIR_ON_OPEN", "EMPTY_DIR");
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  terralod::DemOpenOptions options;
  options.maxBlockBytes = uint64_t{1} << 20;
  const int encoding = data[0] & 3;
  options.encoding = encoding == 1   ? terralod::HeightEncoding::kTerrainRgb
                     : encoding == 2 ? terralod::HeightEncoding::kTerrarium
                                     : terralod::HeightEncoding::kPlain;
  if (encoding == 3) options.band = 1;
  VSILFILE* file =
      VSIFileFromMemBuffer(kPath, const_cast<GByte*>(data + 1), vsi_l_offset(size - 1), FALSE);
  VSIFCloseL(file);
  {
    auto reader = terralod::DemReader::open(kPath, options);
    if (reader) readLikeBuild(**reader, (data[0] >> 2) & 3);
  }
  VSIUnlink(kPath);
  return 0;
}
