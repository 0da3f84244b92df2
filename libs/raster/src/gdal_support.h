#pragma once
// Private helpers around GDAL's global state: one-time driver registration and turning
// GDAL's last error into a one-line message.

#include <cpl_error.h>

#include <string>

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

}  // namespace terralod::gdal
