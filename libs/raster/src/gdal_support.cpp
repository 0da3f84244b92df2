#include "gdal_support.h"

#include <gdal.h>

#include <mutex>

namespace terralod::gdal {

void ensureRegistered() {
  static std::once_flag once;
  std::call_once(once, [] { GDALAllRegister(); });
}

std::string lastErrorMessage() {
  std::string message = CPLGetLastErrorMsg();
  for (char& c : message)
    if (c == '\n' || c == '\r') c = ' ';
  while (!message.empty() && message.back() == ' ') message.pop_back();
  return message;
}

}  // namespace terralod::gdal
