#pragma once
// From a chunk mesh in metres to its stored geometry: heights quantised on the level's step,
// morph targets as deltas, split into 16-bit parts if needed.

#include "terralod/build/chunk_mesher.h"
#include "terralod/build/error_budget.h"
#include "terralod/core/result.h"
#include "terralod/format/chunk_codec.h"

namespace terralod {

Result<ChunkGeometry> quantizeChunk(const ChunkMesh& mesh, const ErrorBudget& budget);

}  // namespace terralod
