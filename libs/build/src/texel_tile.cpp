#include "terralod/build/texel_tile.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <map>
#include <tuple>
#include <utility>

#include "resample_taps.h"

namespace terralod {
namespace {

// Output texel k's centre in source texel coordinates (borders excepted): edge-aligned
// (k / (to - 1) of the side), or where the GPU samples a mip level of `to` texels below one of
// `from` texels ((k + 0.5) * from / to - 0.5).
double centreOf(uint32_t k, uint32_t from, uint32_t to, Placement placement) {
  return placement == Placement::kEdgeAligned ? k * double(from - 1) / double(to - 1)
                                              : (k + 0.5) * double(from) / double(to) - 0.5;
}

std::vector<Taps> makeTaps(uint32_t from, uint32_t to, Placement placement) {
  std::vector<Taps> taps(to);
  const double step = placement == Placement::kEdgeAligned ? double(from - 1) / double(to - 1)
                                                           : double(from) / double(to);
  const double radius = std::max(1.0, step);
  for (uint32_t k = 0; k < to; ++k) {
    Taps& t = taps[k];
    if (k == 0 || k == to - 1) {
      t.first = k == 0 ? 0 : from - 1;
      t.weights = {1.0f};
      continue;
    }
    const double centre = centreOf(k, from, to, placement);
    const int64_t lo = std::max<int64_t>(0, int64_t(std::floor(centre - radius)) + 1);
    const int64_t hi = std::min<int64_t>(from - 1, int64_t(std::ceil(centre + radius)) - 1);
    double sum = 0;
    t.first = uint32_t(lo);
    for (int64_t j = lo; j <= hi; ++j) {
      const double w = 1.0 - std::abs(double(j) - centre) / radius;
      t.weights.push_back(float(std::max(0.0, w)));
      sum += std::max(0.0, w);
    }
    if (t.weights.empty()) {  // centre on a texel with radius 1: that texel
      t.first = uint32_t(std::lround(centre));
      t.weights = {1.0f};
      sum = 1;
    }
    for (float& w : t.weights) w = float(w / sum);
    // A tent sampled at whole texels around a fractional centre is lopsided: tilt it so its
    // centre of mass is the output texel's position (linear functions then resample exactly).
    double m1 = 0, m2 = 0;
    for (size_t i = 0; i < t.weights.size(); ++i) {
      const double d = double(t.first + i) - centre;
      m1 += t.weights[i] * d;
      m2 += t.weights[i] * d * d;
    }
    if (m2 > 0 && std::abs(m1) > 1e-12) {
      const double a = -m1 / m2, norm = 1.0 + a * m1;
      for (size_t i = 0; i < t.weights.size(); ++i)
        t.weights[i] = float(t.weights[i] * (1.0 + a * (double(t.first + i) - centre)) / norm);
    }
  }
  return taps;
}

}  // namespace

// Taps depend only on the two sizes, and the same few pairs recur millions of times.
const std::vector<Taps>& tapsFor(uint32_t from, uint32_t to, Placement placement) {
  thread_local std::map<std::tuple<uint32_t, uint32_t, Placement>, std::vector<Taps>> cache;
  const auto key = std::tuple{from, to, placement};
  auto it = cache.find(key);
  if (it == cache.end()) it = cache.emplace(key, makeTaps(from, to, placement)).first;
  return it->second;
}

TexelTile resampleTile(const TexelTile& source, uint32_t size, Placement placement) {
  assert(source.size >= 2 && size >= 2);
  if (size == source.size) return source;
  const uint32_t c = source.channels;
  const std::vector<Taps>& taps = tapsFor(source.size, size, placement);
  // Each output row from one row of column sums (whole source rows at a time, which
  // vectorises), then along it.
  const size_t sourceRow = size_t(source.size) * c;
  thread_local std::vector<float> sums;
  sums.resize(sourceRow);
  TexelTile result(size, c);
  for (uint32_t y = 0; y < size; ++y) {
    const Taps& t = taps[y];
    std::fill(sums.begin(), sums.end(), 0.0f);
    for (size_t i = 0; i < t.weights.size(); ++i)
      addWeightedRow(sums.data(), source.at(0, t.first + uint32_t(i)), t.weights[i], sourceRow);
    float* out = result.at(0, y);
    for (uint32_t x = 0; x < size; ++x, out += c)
      resampleTexel(out, sums.data() + size_t(taps[x].first) * c, taps[x], c);
  }
  return result;
}

TexelTile resampleTile(TexelTile&& source, uint32_t size) {
  if (size == source.size) return std::move(source);
  return resampleTile(static_cast<const TexelTile&>(source), size);
}

TexelTile mipTile(const TexelTile& above, uint32_t size) {
  return resampleTile(above, size, Placement::kMipLevel);
}

namespace {

// Children placed with `stride` texels between their origins (n - 1 sharing borders, n not),
// missing ones filled from the nearest existing texels (chunks exist from the south-west).
TexelTile placeChildren(const std::array<const TexelTile*, 4>& children, uint32_t stride) {
  const TexelTile* any = nullptr;
  for (const TexelTile* t : children)
    if (t) any = t;
  assert(any);
  const uint32_t n = any->size, c = any->channels, m = stride + n;
  TexelTile result(m, c);
  std::vector<uint8_t> filled(size_t(m) * m, 0);
  for (int q = 0; q < 4; ++q) {
    const TexelTile* t = children[size_t(q)];
    if (!t) continue;
    assert(t->size == n && t->channels == c);
    const uint32_t ox = (q & 1) * stride, oy = (q >> 1) * stride;
    for (uint32_t y = 0; y < n; ++y) {
      std::memcpy(result.at(ox, oy + y), t->at(0, y), sizeof(float) * n * c);
      std::fill_n(filled.begin() + std::ptrdiff_t(size_t(oy + y) * m + ox), n, uint8_t(1));
    }
  }
  // Missing quadrants lie east or north of existing ones: extend rows eastwards, then whole
  // rows northwards.
  for (uint32_t y = 0; y < m; ++y) {
    const uint8_t* f = filled.data() + size_t(y) * m;
    if (!f[0]) continue;
    for (uint32_t x = 1; x < m; ++x)
      if (!f[x]) std::memcpy(result.at(x, y), result.at(x - 1, y), sizeof(float) * c);
    std::fill_n(filled.begin() + std::ptrdiff_t(size_t(y) * m), m, uint8_t(1));
  }
  for (uint32_t y = 1; y < m; ++y)
    if (!filled[size_t(y) * m])
      std::memcpy(result.at(0, y), result.at(0, y - 1), sizeof(float) * m * c);
  return result;
}

const TexelTile* anyOf(const std::array<const TexelTile*, 4>& children) {
  for (const TexelTile* t : children)
    if (t) return t;
  return nullptr;
}

}  // namespace

TexelTile mosaicTiles(const std::array<const TexelTile*, 4>& children) {
  return placeChildren(children, anyOf(children)->size - 1);
}

TexelTile concatTiles(const std::array<const TexelTile*, 4>& children) {
  return placeChildren(children, anyOf(children)->size);
}

}  // namespace terralod
