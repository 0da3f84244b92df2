#pragma once
// The static RTIN chunk kind's stored form (MeshKind::kStaticRtin): a geometry blob
// (chunk_codec) and, in textured tilesets, a texture blob (texture_codec). Decoding needs no
// GPU and is thread-safe.

#include <optional>
#include <string>

#include "terralod/format/chunk_codec.h"
#include "terralod/format/node_bytes.h"
#include "terralod/format/texture_codec.h"

namespace terralod {

/// Everything stored for one static chunk.
struct ChunkData {
  ChunkGeometry geometry;
  std::optional<ChunkTexture> texture;  ///< textured (version 2) tilesets
  uint64_t bytesRead = 0;               ///< stored bytes read for it
};

/// Decodes a static chunk's geometry and (when there is one) texture; `subject` names the
/// chunk in errors.
Result<ChunkData> decodeStaticChunk(const NodeBytes& bytes, const std::string& subject);

}  // namespace terralod
