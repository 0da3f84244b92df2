#include "terralod/build/height_source.h"

#include <algorithm>
#include <cstring>

namespace terralod {

Status readWithMargin(HeightWindows& windows, int32_t x0, int32_t y0, int32_t side, int32_t margin,
                      std::vector<float>& margined, float* closed, unsigned worker) {
  if (margin <= 0) return windows.read(x0, y0, side + 1, side + 1, closed, worker);
  const int32_t stride = side + 1 + 2 * margin;
  margined.resize(size_t(stride) * size_t(stride));
  if (Status st = windows.read(x0 - margin, y0 - margin, stride, stride, margined.data(), worker);
      !st)
    return st;
  for (int32_t y = 0; y <= side; ++y)
    std::copy_n(margined.data() + size_t(y + margin) * size_t(stride) + size_t(margin), side + 1,
                closed + size_t(y) * size_t(side + 1));
  return {};
}

Status MemoryHeights::read(int32_t x0, int32_t y0, int32_t w, int32_t h, float* out, unsigned) {
  const int32_t cols = mHeights.columns(), rows = mHeights.rows();
  for (int32_t y = 0; y < h; ++y) {
    const float* src = mHeights.row(std::clamp(y0 + y, 0, rows - 1));
    float* dst = out + size_t(y) * w;
    // Copy the inside run in one go and replicate the edges around it.
    const int32_t insideLo = std::clamp(0 - x0, 0, w), insideHi = std::clamp(cols - x0, 0, w);
    for (int32_t x = 0; x < insideLo; ++x) dst[x] = src[0];
    if (insideHi > insideLo)
      std::memcpy(dst + insideLo, src + x0 + insideLo, sizeof(float) * (insideHi - insideLo));
    for (int32_t x = std::max(insideHi, insideLo); x < w; ++x) dst[x] = src[cols - 1];
  }
  return {};
}

}  // namespace terralod
