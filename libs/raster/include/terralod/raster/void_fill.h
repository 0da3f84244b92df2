#pragma once
// Filling voids (nodata, NaN) in elevation grids.
//
// Method (documented in docs/format.md, "Voids"): pull-push interpolation. A pyramid is built
// by averaging the valid samples of each 2x2 block ("pull"); then, from the coarsest level
// down, every void sample starts from the bilinear interpolation of the level above and is
// relaxed towards the average of its four neighbours ("push" plus Jacobi relaxation of
// Laplace's equation). The result is a smooth membrane that meets the valid samples around
// each void; valid samples are never changed. O(samples) time, and memory for the pyramid (a
// third more than the grid) plus two rows; rows without voids are skipped when relaxing.

#include <cstdint>
#include <string>

#include "terralod/core/result.h"
#include "terralod/raster/heightfield.h"

namespace terralod {

/// Counts voids (NaN) in the grid.
uint64_t countVoids(const Heightfield& heights);

/// Fills every NaN sample; returns how many were filled. Fails when every sample is a void.
/// `subject` names the source in error messages.
Result<uint64_t> fillVoids(Heightfield& heights, const std::string& subject);

}  // namespace terralod
