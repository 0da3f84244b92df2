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
      mMax(std::max(1u, workers), -std::numeric_limits<double>::infinity()),
      mKept(std::max(1u, workers), 0) {}

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
  if (mKeep) {
    const int32_t cols = mKeep->columns(), rows = mKeep->rows();
    const int32_t xBegin = std::max(x0, 0), yBegin = std::max(y0, 0);
    const int32_t xEnd = x0 + w - 1 >= cols - 1 ? cols : x0 + w - 1;
    const int32_t yEnd = y0 + h - 1 >= rows - 1 ? rows : y0 + h - 1;
    if (xBegin < xEnd && yBegin < yEnd) {
      for (int32_t y = yBegin; y < yEnd; ++y)
        std::copy_n(out + size_t(y - y0) * size_t(w) + size_t(xBegin - x0), xEnd - xBegin,
                    mKeep->row(y) + xBegin);
      mKept[worker] += uint64_t(xEnd - xBegin) * uint64_t(yEnd - yBegin);
    }
  }
  return {};
}

void DemWindows::keepInto(Heightfield& field) {
  mKeep = &field;
  std::fill(mKept.begin(), mKept.end(), uint64_t{0});
}

bool DemWindows::keptAll() const {
  if (!mKeep) return false;
  uint64_t kept = 0;
  for (uint64_t k : mKept) kept += k;
  return kept == uint64_t(mKeep->columns()) * uint64_t(mKeep->rows());
}

double DemWindows::minHeight() const {
  return *std::min_element(mMin.begin(), mMin.end());
}
double DemWindows::maxHeight() const {
  return *std::max_element(mMax.begin(), mMax.end());
}

}  // namespace terralod
