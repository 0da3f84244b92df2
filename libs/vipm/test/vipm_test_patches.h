#pragma once
// Patches for the VIPM tests: windows of real DEMs with a simple material classification,
// and synthetic ones.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "terralod/raster/dem_reader.h"
#include "terralod/vipm/grid_patch.h"

namespace terralod::test {

/// Materials by height band: 0 below `low`, 1 up to `high`, 2 above (three regions with
/// irregular boundaries on real terrain).
inline GridPatch demPatch(const std::string& file, int32_t x0, int32_t y0, float low, float high,
                          int32_t size = 65) {
  GridPatch p;
  p.width = p.height = size;
  p.heights.resize(size_t(size) * size);
  auto dem = DemReader::open(std::string(TERRALOD_TEST_DATA) + "/" + file, {});
  EXPECT_TRUE(dem.ok()) << (dem.ok() ? "" : dem.error().message);
  if (!dem.ok()) return p;
  EXPECT_TRUE((*dem)->readWindow(x0, y0, size, size, p.heights.data()).ok());
  p.materials.resize(p.heights.size());
  for (size_t i = 0; i < p.heights.size(); ++i)
    p.materials[i] = p.heights[i] < low ? 0 : p.heights[i] < high ? 1 : 2;
  return p;
}

/// A smooth synthetic surface (no data needed), one material.
inline GridPatch wavyPatch(int32_t w, int32_t h) {
  GridPatch p;
  p.width = w;
  p.height = h;
  for (int32_t y = 0; y < h; ++y)
    for (int32_t x = 0; x < w; ++x)
      p.heights.push_back(float(10.0 * std::sin(x * 0.2) * std::cos(y * 0.15) + 0.05 * x * y));
  p.materials.assign(p.heights.size(), 0);
  return p;
}

/// A sparse patch over a wavy surface of `cells` + 1 points a side (a node above the roots):
/// its points every `stride` grid points, its start their grid triangulation, its samples
/// bounded over blocks of `step` points.
struct SparseStart {
  GridPatch patch;
  std::vector<std::array<uint16_t, 3>> triangles;
};
inline SparseStart wavySparsePatch(int32_t cells, int32_t stride, int32_t step) {
  SparseStart s;
  GridPatch& p = s.patch;
  p.width = p.height = cells + 1;
  auto z = [](int32_t x, int32_t y) {
    return float(10.0 * std::sin(x * 0.02) * std::cos(y * 0.015) + 0.0005 * x * y);
  };
  const int32_t n = cells / stride + 1;
  for (int32_t j = 0; j < n; ++j)
    for (int32_t i = 0; i < n; ++i) {
      p.pointX.push_back(i * stride);
      p.pointY.push_back(j * stride);
      p.heights.push_back(z(i * stride, j * stride));
      p.materials.push_back(0);
    }
  for (int32_t j = 0; j + 1 < n; ++j)
    for (int32_t i = 0; i + 1 < n; ++i) {
      const auto a = uint16_t(j * n + i), b = uint16_t(a + 1), c = uint16_t(a + n),
                 d = uint16_t(c + 1);
      s.triangles.push_back({a, b, d});
      s.triangles.push_back({a, d, c});
    }
  p.samples = makeSampleBlocks(cells + 1, cells + 1, step, z);
  return s;
}

/// The identity renaming of `n` vertices (for renamed()).
inline std::vector<uint16_t> unrenamed(uint32_t n) {
  std::vector<uint16_t> to(n);
  std::iota(to.begin(), to.end(), uint16_t{0});
  return to;
}

/// A naive replay, the oracle for collapses: every corner renamed through `to` (followed until
/// it names itself), the triangles that became degenerate dropped.
inline std::vector<std::array<uint16_t, 3>> renamed(
    const std::vector<std::array<uint16_t, 3>>& triangles, const std::vector<uint16_t>& to) {
  auto resolve = [&](uint16_t v) {
    while (to[v] != v) v = to[v];
    return v;
  };
  std::vector<std::array<uint16_t, 3>> out;
  for (const auto& t : triangles) {
    const std::array<uint16_t, 3> r{resolve(t[0]), resolve(t[1]), resolve(t[2])};
    if (r[0] != r[1] && r[1] != r[2] && r[0] != r[2]) out.push_back(r);
  }
  return out;
}

}  // namespace terralod::test
