#pragma once
// Pass 1 over one block of the grid: the conservative error of every bintree triangle inside
// the block, bottom-up, turned into saturated vertex activations (see activation_pass.h).

#include <array>
#include <cstdint>
#include <utility>
#include <vector>

#include "terralod/build/activation_grid.h"
#include "terralod/build/activation_pass.h"
#include "terralod/build/error_budget.h"
#include "terralod/core/bintree.h"
#include "triangle_scan.h"

namespace terralod {

/// Error bounds of a vertex's two slot triangles (slot order of diamondTriangles()).
struct SlotErrors {
  float above[2];
  float below[2];
};

/// Per-thread buffers, reused from block to block.
struct BlockScratch {
  std::vector<SlotErrors> slots;
  std::vector<uint8_t> activation;
  std::vector<float> heights;  ///< (side+1)^2 window, filled by the caller
  void reset(int32_t side);
};

struct BlockResult {
  std::vector<std::pair<GridPoint, uint8_t>> border;  ///< one-sided activations, global coords
  std::array<TriangleErrorBounds, 2> squareErrors;    ///< the block square's two triangles
  bool computed = false;
};

struct BlockGeometry {
  int32_t side = 0;   ///< cells
  GridPoint origin;   ///< global grid point of the block's south-west corner
  int32_t realX = 0;  ///< last local column holding data (< side when the data ends inside)
  int32_t realY = 0;
};

/// Computes the block from scratch.heights; writes interior activations into `grid` (never a
/// byte another block writes) and border ones into `out`.
void computeBlock(const BlockGeometry& block, const ErrorBudget& budget, BlockScratch& scratch,
                  ActivationGrid& grid, BlockResult& out, ActivationStats& stats);

}  // namespace terralod
