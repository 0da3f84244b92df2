#pragma once
// Between a chunk's progressive mesh and its stored form (format/vipm_chunk_codec.h):
// height quantisation (chosen before the collapse order is built, so recorded errors include
// it), packing with quantised errors rounded up (so a stored error never understates the
// true one, and rounding keeps them non-decreasing), and unpacking for reconstruction.

#include <array>
#include <cstdint>
#include <vector>

#include "terralod/core/result.h"
#include "terralod/format/vipm_chunk_codec.h"
#include "terralod/vipm/grid_patch.h"
#include "terralod/vipm/progressive_mesh.h"

namespace terralod {

/// Stored heights: zBase + q * zStep, q a u16.
struct HeightQuantisation {
  double zBase = 0.0;
  double zStep = 1.0;
};

/// A power-of-two step no coarser than maxError / 8 (coarser only when the patch's height
/// range needs it to fit 16 bits), and a base on that step at or below the lowest height.
HeightQuantisation chooseQuantisation(const GridPatch& patch, double maxError);

/// Sets patch.vertexHeights to the heights as stored.
void quantiseVertexHeights(GridPatch& patch, const HeightQuantisation& q);

/// The stored form of `mesh`, built from `patch` (whose vertexHeights are quantised with `q`).
VipmChunkData packChunk(const GridPatch& patch, const ProgressiveMesh& mesh,
                        const HeightQuantisation& q);

/// A stored chunk ready for reconstruction.
struct UnpackedChunk {
  ProgressiveMesh mesh;                         ///< errors as stored (rounded up)
  std::vector<std::array<float, 3>> positions;  ///< per vertex: grid x, grid y, height (m)
  std::vector<uint8_t> materials;               ///< per vertex
};
UnpackedChunk unpackChunk(const VipmChunkData& chunk);

}  // namespace terralod
