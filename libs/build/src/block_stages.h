#pragma once
// Pass 1 of one block on its own, as a cluster build's block job runs it: the activations of the
// block's closed square (border points one-sided, as computeBlock leaves them), the errors of the
// block square for the reduce, and what the window showed of the heights.

#include <cstdint>
#include <vector>

#include "block_pass.h"
#include "border_reduce.h"
#include "terralod/build/activation_grid.h"
#include "terralod/build/halo.h"

namespace terralod {

struct Pass1Block {
  ActivationGrid grid;  ///< window over the closed square
  BlockSquare square;
  double minHeight = 0, maxHeight = 0;
  bool sawVoid = false;
  ActivationStats stats;
};

/// `window` holds the (block+1)² heights of the closed square at `origin`.
Pass1Block pass1Block(const TreeLayout& layout, const ErrorBudget& budget, GridPoint origin,
                      int32_t block, const float* window, BlockScratch& scratch);

/// The block's values at its halo's points, in the pattern's order.
std::vector<uint8_t> haloValues(const ActivationGrid& window, const HaloPattern& halo);
/// Writes the finished halo values back into the block's window.
void applyHalo(ActivationGrid& window, const HaloPattern& halo, const std::vector<uint8_t>& values);

}  // namespace terralod
