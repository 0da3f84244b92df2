#include "gdal_support.h"

#include <gdal.h>
#include <gdal_utils.h>

#include <cstdio>
#include <cstdlib>
#include <mutex>

namespace terralod::gdal {

void ensureRegistered() {
  static std::once_flag once;
  std::call_once(once, [] {
    // PROJ prints its errors to stderr from contexts GDAL does not route through CPLError
    // (libgeotiff's, e.g. "proj_uom_get_info_from_database: unit of measure not found" for a
    // GeoTIFF with an unknown unit code: found by the raster fuzzer), which would add a line to
    // terralod's one-line errors. Every failure that matters surfaces through GDAL anyway, so
    // PROJ stays quiet unless PROJ_DEBUG asks otherwise. It is read when PROJ's first context
    // is made, so this comes before anything GDAL does.
    setenv("PROJ_DEBUG", "0", /*overwrite=*/0);
    GDALAllRegister();
  });
}

std::string lastErrorMessage() {
  std::string message = CPLGetLastErrorMsg();
  for (char& c : message)
    if (c == '\n' || c == '\r') c = ' ';
  while (!message.empty() && message.back() == ' ') message.pop_back();
  return message;
}

std::string exactNumber(double v) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.17g", v);
  return buffer;
}

Dataset warp(GDALDatasetH source, std::vector<std::string> args) {
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  GDALWarpAppOptions* options = GDALWarpAppOptionsNew(argv.data(), nullptr);
  if (!options) return nullptr;
  int usageError = 0;
  GDALDatasetH sources[1] = {source};
  Dataset warped(GDALWarp("", nullptr, 1, sources, options, &usageError));
  GDALWarpAppOptionsFree(options);
  return warped;
}

}  // namespace terralod::gdal
