#include "terralod/format/static_chunk.h"

namespace terralod {

Result<ChunkData> decodeStaticChunk(const NodeBytes& bytes, const std::string& subject) {
  ChunkData data;
  data.bytesRead = bytes.bytes.size();
  auto geometry = decodeChunk(bytes.mesh(), subject);
  if (!geometry) return geometry.error();
  data.geometry = std::move(geometry).value();
  if (!bytes.texture().empty()) {
    auto texture = decodeTexture(bytes.texture(), subject);
    if (!texture) return texture.error();
    data.texture = std::move(texture).value();
  }
  return data;
}

}  // namespace terralod
