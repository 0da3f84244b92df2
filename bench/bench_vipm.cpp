// VIPM chunk generation and reconstruction on real DEM windows (tests/data): the grid
// collapser (collapse_order.h) per 65 x 65 chunk with and without the material rules, and the
// O(n) reconstruction (vipm_levels.h). Materials: three height bands.
//
//   build/release/bench/bench_vipm [--benchmark_filter=...]
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "terralod/raster/dem_reader.h"
#include "terralod/vipm/collapse_order.h"
#include "terralod/vipm/progressive_mesh.h"
#include "terralod/vipm/vipm_levels.h"

namespace {

using namespace terralod;

// Chunks of a DEM at (64 i, 64 j), materials by the window's height terciles.
std::vector<GridPatch> chunks(const std::string& file, int count) {
  auto dem = DemReader::open(std::string(TERRALOD_TEST_DATA_DIR) + "/" + file, {});
  if (!dem.ok()) return {};
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

void collapseOrder(benchmark::State& state, const char* file, MaterialRules rules) {
  const auto patches = chunks(file, 8);
  if (patches.empty()) return state.SkipWithError("no data");
  size_t k = 0, collapses = 0;
  for (auto _ : state) {
    const CollapseOrder order = buildCollapseOrder(patches[k++ % patches.size()], rules);
    collapses += order.collapses.size();
    benchmark::DoNotOptimize(order);
  }
  state.counters["collapses_per_chunk"] = double(collapses) / double(state.iterations());
}

void reconstruct(benchmark::State& state, const char* file) {
  const auto patches = chunks(file, 8);
  if (patches.empty()) return state.SkipWithError("no data");
  std::vector<ProgressiveMesh> meshes;
  std::vector<std::vector<uint8_t>> materials;
  for (const GridPatch& p : patches) {
    meshes.push_back(makeProgressiveMesh(p, buildCollapseOrder(p, MaterialRules::kOn), 1.0));
    materials.emplace_back();
    for (uint16_t point : meshes.back().points) materials.back().push_back(p.materials[point]);
  }
  size_t k = 0;
  for (auto _ : state) {
    const size_t i = k++ % meshes.size();
    auto levels = VipmLevels::reconstruct(meshes[i], materials[i]);
    benchmark::DoNotOptimize(levels);
  }
}

BENCHMARK_CAPTURE(collapseOrder, crater_rules, "crater_lake_0513.bt", MaterialRules::kOn)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(collapseOrder, crater_no_rules, "crater_lake_0513.bt", MaterialRules::kOff)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(collapseOrder, zion_rules, "zion_srtm3_utm12_30m.tif", MaterialRules::kOn)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(reconstruct, crater, "crater_lake_0513.bt")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(reconstruct, zion, "zion_srtm3_utm12_30m.tif")->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
