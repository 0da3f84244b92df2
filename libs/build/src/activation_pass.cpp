#include "terralod/build/activation_pass.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <vector>

#include "block_pass.h"
#include "border_reduce.h"
#include "terralod/build/kept_heights.h"
#include "terralod/core/bintree.h"
#include "terralod/core/parallel.h"
#include "triangle_scan.h"

namespace terralod {

Result<ActivationGrid> computeActivations(const TreeLayout& layout, const ErrorBudget& budget,
                                          HeightWindows& windows, const HeightSampler& points,
                                          const ActivationOptions& options, Progress& progress,
                                          ActivationStats* stats) {
  const int32_t block = std::clamp(options.blockCells, layout.leafCells, layout.rootCells);
  ActivationGrid grid(layout.gridX(), layout.gridY());
  const int32_t blocksX = layout.gridX() / block, blocksY = layout.gridY() / block;
  const unsigned threads = std::max(1u, options.threads);

  std::vector<BlockResult> results(size_t(blocksX) * blocksY);
  std::vector<BlockScratch> scratch(threads);
  const int32_t margin = options.user ? options.user->margin() : 0;
  std::vector<std::vector<float>> margined(threads);  // windows with the margin (margin > 0)
  std::vector<ActivationStats> workerStats(threads);
  std::vector<Status> workerStatus(threads);
  std::atomic<bool> failed{false};

  progress.begin("errors", results.size());
  parallelFor(results.size(), threads, [&](size_t i, unsigned worker) {
    progress.advance();
    if (failed) return;
    const int32_t bx = int32_t(i % blocksX) * block, by = int32_t(i / blocksX) * block;
    if (bx >= layout.cellsX || by >= layout.cellsY) return;  // wholly padding: all zero
    BlockScratch& s = scratch[worker];
    s.reset(block);
    const Status st =
        readWithMargin(windows, bx, by, block, margin, margined[worker], s.heights.data(), worker);
    if (!st) {
      workerStatus[worker] = st;
      failed = true;
      return;
    }
    BlockGeometry geometry;
    geometry.side = block;
    geometry.origin = {bx, by};
    geometry.realX = std::min(block, layout.cellsX - bx);
    geometry.realY = std::min(block, layout.cellsY - by);
    computeBlock(geometry, budget, s, grid, results[i], workerStats[worker]);
    if (options.keep) options.keep->keepBlock(geometry.origin, s.heights.data(), grid);
    if (options.user)
      if (Status used = options.user->useBlock(
              bx, by, block, margin > 0 ? margined[worker].data() : s.heights.data(), worker);
          !used) {
        workerStatus[worker] = used;
        failed = true;
      }
  });
  progress.end();
  for (const Status& st : workerStatus)
    if (!st) return st.error();

  // Borders: the maximum of both sides' one-sided activations.
  for (const BlockResult& r : results)
    for (const auto& [p, a] : r.border)
      if (grid.get(p.x, p.y) < a) grid.set(p.x, p.y, a);

  std::vector<BlockSquare> squares(results.size());
  for (size_t i = 0; i < results.size(); ++i)
    squares[i] = {results[i].squareErrors, results[i].computed};
  finishBorders(layout, budget, points, grid, block, squares);

  if (stats) {
    for (const ActivationStats& w : workerStats) {
      stats->trianglesScanned += w.trianglesScanned;
      stats->trianglesBounded += w.trianglesBounded;
    }
  }
  return grid;
}

}  // namespace terralod
