#pragma once
// Private helpers around GDAL: one-time driver registration, GDAL's last error as a one-line
// message, datasets that close themselves, and warping onto a grid. Private to terralod_raster
// (libs/materials includes it too and links what it needs).

#include <cpl_error.h>
#include <gdal.h>

#include <memory>
#include <string>
#include <vector>

namespace terralod::gdal {

/// Registers GDAL drivers once per process (thread-safe).
void ensureRegistered();

/// GDAL's most recent error message on this thread, cleaned to one line ("" if none).
std::string lastErrorMessage();

/// Silences GDAL's default stderr printing for the lifetime of the object on this thread;
/// errors are still recorded and read back with lastErrorMessage().
class QuietErrors {
 public:
  QuietErrors() {
    CPLPushErrorHandler(CPLQuietErrorHandler);
    CPLErrorReset();
  }
  ~QuietErrors() { CPLPopErrorHandler(); }
  QuietErrors(const QuietErrors&) = delete;
  QuietErrors& operator=(const QuietErrors&) = delete;
};

struct DatasetCloser {
  void operator()(void* dataset) const {
    if (dataset) GDALClose(dataset);
  }
};
/// An open GDAL dataset, closed when it goes out of scope.
using Dataset = std::unique_ptr<void, DatasetCloser>;

/// `v` with every digit a double holds, for GDAL's text options ("%.17g").
std::string exactNumber(double v);

/// gdalwarp with command-line `args` (e.g. -of VRT -te ... -ts ... -r near) on `source`,
/// unnamed. Null when the options are refused or the warp fails (lastErrorMessage() says why).
Dataset warp(GDALDatasetH source, std::vector<std::string> args);

}  // namespace terralod::gdal
