#pragma once
// The reduce step of pass 1: finishing the block borders. Pass 1 computes every block alone;
// once both sides of each border are merged (their maximum), this computes the triangles larger
// than a block (from their children's bounds, on the lattice of block corners, border midpoints
// and centres) and raises every point to at least the activation of the points depending on it,
// starting from the borders. `Store` is the whole ActivationGrid (a local build) or a HaloStore
// (a cluster build's reduce job): both see the same points change the same way.

#include <array>
#include <vector>

#include "terralod/build/error_budget.h"
#include "terralod/build/height_source.h"
#include "terralod/build/tree_layout.h"
#include "triangle_scan.h"

namespace terralod {

/// Pass 1's errors for the two triangles of one block's square.
struct BlockSquare {
  std::array<TriangleErrorBounds, 2> errors{};
  bool computed = false;  ///< false for blocks wholly outside the data (all zero)
};

/// Runs after the borders are merged. `points` gives heights on the block grid lines;
/// `squares` has one entry per block, row-major.
template <class Store>
void finishBorders(const TreeLayout& layout, const ErrorBudget& budget, const HeightSampler& points,
                   Store& store, int32_t block, const std::vector<BlockSquare>& squares);

}  // namespace terralod
