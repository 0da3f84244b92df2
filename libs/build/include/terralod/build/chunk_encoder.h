#pragma once
// From a chunk mesh in metres to its stored geometry: heights quantised on the level's step,
// morph targets as deltas, split into 16-bit parts if needed; the skirts stored (payload
// version 1) or left for the reader to derive from each side's depth (version 2).

#include "terralod/build/chunk_mesher.h"
#include "terralod/build/error_budget.h"
#include "terralod/core/result.h"
#include "terralod/format/chunk_codec.h"

namespace terralod {

Result<ChunkGeometry> quantizeChunk(const ChunkMesh& mesh, const ErrorBudget& budget,
                                    ChunkPayloadVersion payload);

}  // namespace terralod
