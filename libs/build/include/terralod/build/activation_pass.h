#pragma once
// Computes the ActivationGrid: for every RTIN vertex, the largest conservative error of the
// (up to two) triangles it splits, quantised against the per-level thresholds and saturated so
// that meshes are conforming and nested.
//
// A triangle's error is max |h(s) - plane(s)| over the data samples s inside it (closed), so a
// mesh of unsplit triangles is within the threshold at every sample, not just at vertices.
// Errors are computed bottom-up in blocks of the grid. Each triangle first gets a cheap upper
// bound from its children (max child error + the midpoint's offset from its plane); only when
// that bound could change the vertex's saturated activation is the triangle scanned exactly.
// The result equals scanning every triangle exactly, at a fraction of the cost. Triangles
// larger than a block use the bound alone. Block borders are finished in a serial pass that
// merges both sides and propagates increases to dependent vertices.

#include <cstdint>

#include "terralod/build/activation_grid.h"
#include "terralod/build/error_budget.h"
#include "terralod/build/height_source.h"
#include "terralod/build/tree_layout.h"
#include "terralod/core/progress.h"
#include "terralod/core/result.h"

namespace terralod {

class KeptHeights;

/// Work that reads each block's heights while pass 1 has them (the texture pass of a build that
/// keeps no raster for pass 2). Pass 1 reads margin() more samples on every side of each block
/// for it.
class BlockWindowUser {
 public:
  virtual ~BlockWindowUser() = default;
  virtual int32_t margin() const = 0;
  /// The block of `side` cells at grid point (x0, y0): (side + 1 + 2 margin)² heights from
  /// (x0 - margin, y0 - margin), in rows. Called from pass 1's workers, concurrently.
  virtual Status useBlock(int32_t x0, int32_t y0, int32_t side, const float* heights,
                          unsigned worker) = 0;
};

struct ActivationOptions {
  int32_t blockCells = 512;  ///< side of a block (power of two, <= rootCells, >= leafCells)
  unsigned threads = 1;
  KeptHeights* keep = nullptr;      ///< keeps each block's heights that pass 2 reads (optional)
  BlockWindowUser* user = nullptr;  ///< given each block's window too (optional)
};

struct ActivationStats {
  uint64_t trianglesScanned = 0;  ///< triangles whose error was computed exactly
  uint64_t trianglesBounded = 0;  ///< triangles settled by the bound alone
};

Result<ActivationGrid> computeActivations(const TreeLayout& layout, const ErrorBudget& budget,
                                          HeightWindows& windows, const HeightSampler& points,
                                          const ActivationOptions& options, Progress& progress,
                                          ActivationStats* stats = nullptr);

}  // namespace terralod
