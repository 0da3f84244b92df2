#pragma once
// Chunk blobs: the geometry of one chunk, quantised and compressed with meshoptimizer's vertex
// and index codecs, the whole then compressed with zstd. A blob is
// self-contained: one read at the node's offset gives everything needed to draw the chunk.

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "terralod/core/result.h"

namespace terralod {

/// One vertex as stored and as uploaded to the GPU (8 bytes).
/// World position: x = (chunkX0 + x) * spacingX, y = (chunkY0 + y) * spacingY,
/// z = zBase + (z + t * morphDelta) * zStep for morph parameter t in [0, 1].
struct ChunkVertex {
  uint16_t x = 0, y = 0;   ///< grid cells from the chunk's south-west corner
  uint16_t z = 0;          ///< quantised height
  int16_t morphDelta = 0;  ///< parent surface minus own height, in zStep units
  friend bool operator==(const ChunkVertex&, const ChunkVertex&) = default;
};
static_assert(sizeof(ChunkVertex) == 8);

/// A range of the chunk with its own 16-bit vertex space (almost every chunk has one part;
/// parts keep indices 16-bit when a coarse chunk needs more than 65535 vertices).
struct ChunkPart {
  std::vector<ChunkVertex> vertices;
  std::vector<uint32_t> indices;   ///< triangle list: surface first, then skirts
  uint32_t surfaceIndexCount = 0;  ///< indices [0, surfaceIndexCount) are the surface
};

struct ChunkGeometry {
  double zBase = 0.0;
  double zStep = 1.0;
  std::vector<ChunkPart> parts;
};

/// zstd level of chunk blobs unless a build asks for another (level 3 is within a few percent
/// of level 19 on chunk data, and an order of magnitude faster).
inline constexpr int kDefaultChunkCompressionLevel = 3;

/// Encodes; `compressionLevel` is zstd's level. Parts must have at most 65536 vertices.
std::vector<uint8_t> encodeChunk(const ChunkGeometry& geometry,
                                 int compressionLevel = kDefaultChunkCompressionLevel);

/// Decodes and validates a blob (never trusts it); `subject` names it in errors.
Result<ChunkGeometry> decodeChunk(std::span<const uint8_t> blob, const std::string& subject);

/// Reorders a part's triangles for the post-transform vertex cache and its vertices for fetch
/// locality (meshoptimizer), keeping surface and skirt triangles in their own ranges.
void optimizeChunkPart(ChunkPart& part);

}  // namespace terralod
