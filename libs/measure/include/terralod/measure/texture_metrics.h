#pragma once
// The bench's texture figures:
//  - texel density: how many pixels one texel of each drawn chunk can cover, at most: the
//    texel's size (chunk side / (texels - 1)) times K over the distance from the eye to the
//    chunk's box. Layers the source could not make fine enough (source-limited) are kept apart:
//    the eq. 7 guarantee is about the others.
//  - image pops: the mean absolute change of the rendered pixels between two selections drawn
//    from the same camera (what LOD alone changes in the picture).

#include <span>

#include "terralod/render/gpu_chunk_store.h"
#include "terralod/render/image.h"
#include "terralod/runtime/chunk_tree.h"
#include "terralod/runtime/selection.h"
#include "terralod/runtime/view.h"

namespace terralod {

struct TexelDensity {
  double max = 0.0;               ///< over layers sized by eq. 7
  double sourceLimitedMax = 0.0;  ///< over source-limited layers
  bool any = false, anySourceLimited = false;
};

/// Adds the drawn chunks of one frame to `density`.
void addTexelDensity(const View& view, const ChunkTree& tree, const GpuChunkStore& store,
                     std::span<const SelectedChunk> chunks, TexelDensity& density);

/// Mean over pixels and RGB channels of |a - b|, in 8-bit units (0..255). Same sizes.
double meanAbsoluteDifference(const Image& a, const Image& b);

/// Whether two selections hold different chunks (morph parameters aside).
bool selectionsDiffer(std::span<const SelectedChunk> a, std::span<const SelectedChunk> b);

}  // namespace terralod
