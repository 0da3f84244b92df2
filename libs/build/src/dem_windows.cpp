#include "terralod/build/dem_windows.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace terralod {

DemWindows::DemWindows(const DemReader& reader, unsigned workers, SparseHeights* record)
    : mReader(reader),
      mOwnReaders(std::max(1u, workers)),
      mRecord(record),
      mMin(std::max(1u, workers), std::numeric_limits<double>::infinity()),
      mMax(std::max(1u, workers), -std::numeric_limits<double>::infinity()) {}

Status DemWindows::read(int32_t x0, int32_t y0, int32_t w, int32_t h, float* out, unsigned worker) {
  const DemReader* reader = &mReader;
  if (worker > 0) {
    std::unique_ptr<DemReader>& own = mOwnReaders[worker];
    if (!own) {
      std::lock_guard lock(mOpenMutex);
      auto opened = mReader.reopen();
      if (!opened) return opened.error();
      own = std::move(opened).value();
    }
    reader = own.get();
  }
  if (Status s = reader->readWindow(x0, y0, w, h, out); !s) return s;
  float lo = std::numeric_limits<float>::infinity(), hi = -lo;
  bool sawVoid = false;
  for (size_t i = 0, n = size_t(w) * size_t(h); i < n; ++i) {
    const float v = out[i];
    sawVoid |= std::isnan(v);
    lo = std::min(lo, v);
    hi = std::max(hi, v);
  }
  if (sawVoid) mSawVoid = true;
  mMin[worker] = std::min(mMin[worker], double(lo));
  mMax[worker] = std::max(mMax[worker], double(hi));
  if (mRecord) mRecord->recordLines(x0, y0, w, h, out);
  return {};
}

double DemWindows::minHeight() const {
  return *std::min_element(mMin.begin(), mMin.end());
}
double DemWindows::maxHeight() const {
  return *std::max_element(mMax.begin(), mMax.end());
}

}  // namespace terralod
