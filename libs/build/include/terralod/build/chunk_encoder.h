#pragma once
// From a chunk mesh in metres to its stored geometry: heights quantised on the level's step,
// morph targets as deltas, split into 16-bit parts if needed; the skirts stored (payload
// version 1) or left for the reader to derive from each side's depth (version 2); RTIN chunks
// stored as their bintree's decisions and height residuals (version 3).

#include "terralod/build/chunk_mesher.h"
#include "terralod/build/error_budget.h"
#include "terralod/core/result.h"
#include "terralod/format/chunk_codec.h"

namespace terralod {

Result<ChunkGeometry> quantizeChunk(const ChunkMesh& mesh, const ErrorBudget& budget,
                                    ChunkPayloadVersion payload);

/// A chunk's blob, and its geometry's height scale and skirt steps (and parts, for payloads 1
/// and 2: a bintree blob's reader makes them).
struct EncodedChunk {
  ChunkGeometry geometry;
  std::vector<uint8_t> blob;
  ChunkPayloadVersion payload = ChunkPayloadVersion::kDerivedSkirts;  ///< what `blob` holds
};

/// Quantises and encodes. With kRtinCoded an RTIN chunk is stored as its bintree (payload
/// version 3), a greedy one (no walk decisions) as payload version 2.
Result<EncodedChunk> encodeChunkMesh(const ChunkMesh& mesh, const ErrorBudget& budget,
                                     ChunkPayloadVersion payload, int compressionLevel);

}  // namespace terralod
