#include "terralod/build/leaf_size.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "block_pass.h"
#include "build_steps.h"
#include "terralod/build/builder.h"
#include "terralod/build/dem_windows.h"
#include "terralod/build/error_budget.h"
#include "terralod/build/tree_layout.h"
#include "terralod/core/parallel.h"
#include "terralod/raster/dem_reader.h"

namespace terralod {
namespace {

constexpr int32_t kSampleCells = 256;  // a sample block's side
constexpr int32_t kSamplesPerSide = 4;
constexpr int32_t kMaxAutomaticLeafCells = 256;

}  // namespace

int32_t automaticLeafCells(int32_t rootCells, double trianglesPer64) {
  const int32_t most = std::clamp(rootCells / 8, 64, kMaxAutomaticLeafCells);
  int32_t cells = 64;
  double triangles = trianglesPer64;
  while (cells < most && triangles < kTargetLeafTriangles) {
    cells *= 2;
    triangles *= 4;
  }
  return cells;
}

Result<LeafTriangleEstimate> estimateLeafTriangles(const DemReader& reader, double maxError,
                                                   unsigned threads) {
  const DemInfo& info = reader.info();
  auto layout = makeTreeLayout(info.columns, info.rows, 64);
  if (!layout) return layout.error();
  LeafTriangleEstimate estimate;
  const int32_t blocksX = layout->cellsX / kSampleCells, blocksY = layout->cellsY / kSampleCells;
  if (blocksX < 1 || blocksY < 1 || layout->rootCells < kSampleCells) return estimate;
  const auto [lo, hi] = guessHeightRange(reader);
  auto budget = makeErrorBudget(*layout, maxError, hi - lo);
  if (!budget) return budget.error();

  const int32_t nx = std::min(kSamplesPerSide, blocksX), ny = std::min(kSamplesPerSide, blocksY);
  // The samples on `threads` workers, each with its own reader (DemWindows; the caller's
  // reader is worker 0's).
  struct Sample {
    Status status;
    uint64_t points = 0;
    bool measured = false;
  };
  std::vector<Sample> samples(size_t(nx) * size_t(ny));
  const unsigned workers = std::clamp<unsigned>(threads, 1, unsigned(samples.size()));
  DemWindows windows(reader, workers, nullptr);
  std::vector<BlockScratch> scratches(workers);
  std::vector<ActivationStats> stats(workers);
  parallelFor(samples.size(), workers, [&](size_t k, unsigned worker) {
    Sample& sample = samples[k];
    const int32_t i = int32_t(k % size_t(nx)), j = int32_t(k / size_t(nx));
    const int32_t bx = int32_t((i + 0.5) * blocksX / nx) * kSampleCells;
    const int32_t by = int32_t((j + 0.5) * blocksY / ny) * kSampleCells;
    BlockScratch& scratch = scratches[worker];
    scratch.reset(kSampleCells);
    sample.status =
        windows.read(bx, by, kSampleCells + 1, kSampleCells + 1, scratch.heights.data(), worker);
    if (!sample.status) return;
    if (std::any_of(scratch.heights.begin(), scratch.heights.end(),
                    [](float h) { return std::isnan(h); }))
      return;  // voids are filled before the real pass 1; a sample need not be
    BlockGeometry geometry;
    geometry.side = kSampleCells;
    geometry.origin = {bx, by};
    geometry.realX = geometry.realY = kSampleCells;
    ActivationGrid grid = ActivationGrid::window(bx, by, kSampleCells, kSampleCells);
    BlockResult result;
    computeBlock(geometry, *budget, scratch, grid, result, stats[worker]);
    // The block's inner points: its border lines are shared with its neighbours.
    const size_t stride = size_t(kSampleCells) + 1;
    for (int32_t y = 1; y < kSampleCells; ++y)
      for (int32_t x = 1; x < kSampleCells; ++x)
        sample.points += scratch.activation[size_t(y) * stride + size_t(x)] >= 1;
    sample.measured = true;
  });
  uint64_t points = 0, interior = 0;
  for (const Sample& sample : samples) {
    if (!sample.status) return sample.status.error();
    if (!sample.measured) continue;
    points += sample.points;
    interior += uint64_t(kSampleCells - 1) * (kSampleCells - 1);
    ++estimate.blocks;
  }
  // A triangulation of V points has about 2V triangles.
  if (interior > 0) estimate.trianglesPer64 = 2.0 * double(points) / double(interior) * 64 * 64;
  return estimate;
}

Result<int32_t> leafCellsFor(const BuildOptions& options, const DemReader& reader) {
  if (options.chunkCells != 0 || options.kind != TilesetKind::kStatic) return options.chunkCells;
  // makeTreeLayout's own choice for 0 (at most 64 cells) stands unless roots have room for
  // 128-cell leaves in four levels.
  const DemInfo& info = reader.info();
  auto layout = makeTreeLayout(info.columns, info.rows, 0);
  if (!layout) return layout.error();
  if (layout->rootCells / 8 < 128) return 0;
  const unsigned threads = options.threads ? options.threads : hardwareThreads();
  auto estimate = estimateLeafTriangles(reader, options.maxError, threads);
  if (!estimate) return estimate.error();
  if (estimate->blocks == 0) return 0;
  return automaticLeafCells(layout->rootCells, estimate->trianglesPer64);
}

}  // namespace terralod
