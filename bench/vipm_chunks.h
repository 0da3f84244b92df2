#pragma once
// The VIPM chunks both generation benchmarks (bench_vipm, bench_vipm_openmesh) run on: 65 x 65
// windows of a DEM in tests/data (TERRALOD_TEST_DATA_DIR), materials by the window's height
// terciles.

#include <algorithm>
#include <array>
#include <string>
#include <vector>

#include "terralod/raster/dem_reader.h"
#include "terralod/vipm/grid_patch.h"

namespace terralod::bench {

/// `count` chunks of `file` at (64 i, 64 j), spread over the DEM; empty if it cannot be read.
/// `spacing` (optional) receives the DEM's metres per cell along x and y.
inline std::vector<GridPatch> chunks(const std::string& file, int count,
                                     std::array<double, 2>* spacing = nullptr) {
  auto dem = DemReader::open(std::string(TERRALOD_TEST_DATA_DIR) + "/" + file, {});
  if (!dem.ok()) return {};
  if (spacing) *spacing = {(*dem)->info().spacingX, (*dem)->info().spacingY};
  std::vector<GridPatch> out;
  const int32_t nx = ((*dem)->info().columns - 1) / 64, ny = ((*dem)->info().rows - 1) / 64;
  for (int k = 0; k < count; ++k) {
    const int32_t i = (k * 7) % nx, j = (k * 5 + 1) % ny;
    GridPatch p;
    p.width = p.height = 65;
    p.heights.resize(65 * 65);
    if (!(*dem)->readWindow(i * 64, j * 64, 65, 65, p.heights.data()).ok()) return {};
    std::vector<float> sorted = p.heights;
    std::sort(sorted.begin(), sorted.end());
    const float a = sorted[sorted.size() / 3], b = sorted[2 * sorted.size() / 3];
    for (float h : p.heights) p.materials.push_back(h < a ? 0 : h < b ? 1 : 2);
    out.push_back(std::move(p));
  }
  return out;
}

}  // namespace terralod::bench
