#include "terralod/raster/void_fill.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstddef>
#include <utility>
#include <vector>

namespace terralod {
namespace {

// One level of the pull-push pyramid: values with a validity flag per sample.
struct Level {
  int32_t w = 0, h = 0;
  std::vector<float> value;
  std::vector<uint8_t> valid;
  float at(int32_t x, int32_t y) const {
    return value[size_t(std::clamp(y, 0, h - 1)) * w + std::clamp(x, 0, w - 1)];
  }
};

Level pull(const Level& fine) {
  Level coarse;
  coarse.w = (fine.w + 1) / 2;
  coarse.h = (fine.h + 1) / 2;
  coarse.value.assign(size_t(coarse.w) * coarse.h, 0.0f);
  coarse.valid.assign(coarse.value.size(), 0);
  for (int32_t y = 0; y < coarse.h; ++y) {
    for (int32_t x = 0; x < coarse.w; ++x) {
      double sum = 0;
      int n = 0;
      for (int32_t dy = 0; dy < 2; ++dy) {
        for (int32_t dx = 0; dx < 2; ++dx) {
          const int32_t fx = 2 * x + dx, fy = 2 * y + dy;
          if (fx >= fine.w || fy >= fine.h) continue;
          const size_t i = size_t(fy) * fine.w + fx;
          if (fine.valid[i]) sum += fine.value[i], ++n;
        }
      }
      if (n > 0) {
        coarse.value[size_t(y) * coarse.w + x] = static_cast<float>(sum / n);
        coarse.valid[size_t(y) * coarse.w + x] = 1;
      }
    }
  }
  return coarse;
}

// Relaxes the voids of `fine` towards the mean of their four neighbours, `sweeps` times. Jacobi:
// each sweep reads the values of the sweep before. Instead of a copy of the level, a row's
// values before the sweep are kept in one of two row buffers until the row below has been
// updated; rows without voids are skipped, as they do not change.
void relax(Level& fine, int sweeps) {
  const int32_t w = fine.w, h = fine.h;
  std::vector<uint8_t> rowHasVoid(size_t(h), 0);
  for (int32_t y = 0; y < h; ++y) {
    const auto row = fine.valid.begin() + std::ptrdiff_t(y) * w;
    rowHasVoid[size_t(y)] = std::find(row, row + w, 0) != row + w ? 1 : 0;
  }
  std::vector<float> bufferA(static_cast<size_t>(w)), bufferB(static_cast<size_t>(w));
  for (int sweep = 0; sweep < sweeps; ++sweep) {
    float* spare = bufferA.data();
    float* other = bufferB.data();
    const float* above = nullptr;  // the row above as it was before this sweep
    for (int32_t y = 0; y < h; ++y) {
      float* row = fine.value.data() + size_t(y) * w;
      if (!rowHasVoid[size_t(y)]) {
        above = row;
        continue;
      }
      std::copy(row, row + w, spare);
      const float* old = spare;
      const float* up = y > 0 ? above : old;
      const float* down = y + 1 < h ? row + w : old;  // not yet updated in this sweep
      const uint8_t* valid = fine.valid.data() + size_t(y) * w;
      for (int32_t x = int32_t(std::find(valid, valid + w, 0) - valid); x < w;
           x = int32_t(std::find(valid + x + 1, valid + w, 0) - valid)) {
        row[x] = 0.25f * (old[std::max(x - 1, 0)] + old[std::min(x + 1, w - 1)] + up[x] + down[x]);
      }
      above = old;
      std::swap(spare, other);
    }
  }
}

// Gives every void of `fine` the bilinear interpolation of `coarse` (already complete), then
// relaxes the voids.
void push(Level& fine, const Level& coarse) {
  for (int32_t y = 0; y < fine.h; ++y) {
    const double cy = (y - 0.5) * 0.5;
    const int32_t y0 = static_cast<int32_t>(std::floor(cy));
    const double ty = cy - y0;
    for (int32_t x = 0; x < fine.w; ++x) {
      const size_t i = size_t(y) * fine.w + x;
      if (fine.valid[i]) continue;
      const double cx = (x - 0.5) * 0.5;
      const int32_t x0 = static_cast<int32_t>(std::floor(cx));
      const double tx = cx - x0;
      const double top = coarse.at(x0, y0) * (1 - tx) + coarse.at(x0 + 1, y0) * tx;
      const double bottom = coarse.at(x0, y0 + 1) * (1 - tx) + coarse.at(x0 + 1, y0 + 1) * tx;
      fine.value[i] = static_cast<float>(top * (1 - ty) + bottom * ty);
    }
  }
  constexpr int kRelaxations = 8;
  relax(fine, kRelaxations);
}

}  // namespace

uint64_t SampleMask::count() const {
  uint64_t n = 0;
  for (uint64_t word : mBits) n += uint64_t(std::popcount(word));
  return n;
}

SampleMask seaVoids(const Heightfield& heights) {
  const int32_t w = heights.columns(), h = heights.rows();
  bool edgeVoid = false;
  for (int32_t x = 0; x < w && !edgeVoid; ++x)
    edgeVoid = std::isnan(heights(x, 0)) || std::isnan(heights(x, h - 1));
  for (int32_t y = 0; y < h && !edgeVoid; ++y)
    edgeVoid = std::isnan(heights(0, y)) || std::isnan(heights(w - 1, y));
  if (!edgeVoid) return {};
  SampleMask sea(w, h);
  SampleMask seen(w, h);
  std::vector<std::pair<int32_t, int32_t>> stack, members;
  std::vector<float> rim;
  auto group = [&](int32_t sx, int32_t sy) {
    if (!std::isnan(heights(sx, sy)) || seen.at(sx, sy)) return;
    stack.assign(1, {sx, sy});
    seen.set(sx, sy);
    members.clear();
    rim.clear();
    while (!stack.empty()) {
      const auto [x, y] = stack.back();
      stack.pop_back();
      members.push_back({x, y});
      const std::pair<int32_t, int32_t> next[4] = {{x - 1, y}, {x + 1, y}, {x, y - 1}, {x, y + 1}};
      for (const auto& [nx, ny] : next) {
        if (nx < 0 || ny < 0 || nx >= w || ny >= h) continue;
        const float v = heights(nx, ny);
        if (!std::isnan(v)) {
          rim.push_back(v);
        } else if (!seen.at(nx, ny)) {
          seen.set(nx, ny);
          stack.push_back({nx, ny});
        }
      }
    }
    const size_t low = size_t(std::count_if(rim.begin(), rim.end(),
                                            [](float v) { return v <= float(kSeaVoidRimHeight); }));
    if (rim.empty() || 4 * low < rim.size()) return;
    for (const auto& [x, y] : members) sea.set(x, y);
  };
  for (int32_t x = 0; x < w; ++x) {
    group(x, 0);
    group(x, h - 1);
  }
  for (int32_t y = 0; y < h; ++y) {
    group(0, y);
    group(w - 1, y);
  }
  return sea;
}

uint64_t countVoids(const Heightfield& heights) {
  uint64_t voids = 0;
  for (float v : heights.values()) voids += std::isnan(v) ? 1 : 0;
  return voids;
}

Result<uint64_t> fillVoids(Heightfield& heights, const std::string& subject) {
  const uint64_t voids = countVoids(heights);
  if (voids == 0) return uint64_t{0};
  if (voids == heights.values().size())
    return makeError(subject, "every sample is nodata; there is no terrain to build");

  std::vector<Level> pyramid(1);
  pyramid[0].w = heights.columns();
  pyramid[0].h = heights.rows();
  pyramid[0].value.assign(heights.values().begin(), heights.values().end());
  pyramid[0].valid.resize(pyramid[0].value.size());
  for (size_t i = 0; i < pyramid[0].value.size(); ++i) {
    pyramid[0].valid[i] = std::isnan(pyramid[0].value[i]) ? 0 : 1;
    if (!pyramid[0].valid[i]) pyramid[0].value[i] = 0.0f;
  }
  // Pull until a level has no voids (at worst a single sample, which is valid).
  auto hasVoid = [](const Level& l) {
    return std::find(l.valid.begin(), l.valid.end(), 0) != l.valid.end();
  };
  while (hasVoid(pyramid.back())) pyramid.push_back(pull(pyramid.back()));
  for (size_t k = pyramid.size() - 1; k-- > 0;) push(pyramid[k], pyramid[k + 1]);

  Heightfield::Values& out = heights.values();
  for (size_t i = 0; i < out.size(); ++i)
    if (std::isnan(out[i])) out[i] = pyramid[0].value[i];
  return voids;
}

}  // namespace terralod
