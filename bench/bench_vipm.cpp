// VIPM chunk generation and reconstruction on real DEM windows (tests/data): the grid
// collapser (collapse_order.h) per 65 x 65 chunk with and without the material rules, and the
// O(n) reconstruction (vipm_levels.h). Materials: three height bands (vipm_chunks.h).
//
//   build/release/bench/bench_vipm [--benchmark_filter=...]
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "terralod/vipm/collapse_order.h"
#include "terralod/vipm/progressive_mesh.h"
#include "terralod/vipm/vipm_levels.h"
#include "vipm_chunks.h"

namespace {

using namespace terralod;

using bench::chunks;

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
