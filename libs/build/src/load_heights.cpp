#include "load_heights.h"

#include <algorithm>

namespace terralod {

Result<Heightfield> loadHeights(const DemReader& reader, Progress& progress) {
  const DemInfo& info = reader.info();
  Heightfield heights(info.columns, info.rows);
  constexpr int32_t kStrip = 256;
  progress.begin("reading", uint64_t(info.rows));
  for (int32_t y = 0; y < info.rows; y += kStrip) {
    const int32_t n = std::min(kStrip, info.rows - y);
    if (Status s = reader.readWindow(0, y, info.columns, n, heights.row(y)); !s) return s.error();
    progress.advance(uint64_t(n));
  }
  progress.end();
  return heights;
}

}  // namespace terralod
