#pragma once
// Chunk blobs: the geometry of one chunk, quantised and compressed with meshoptimizer's vertex
// and index codecs, the whole then compressed with zstd. A blob is
// self-contained: one read at the node's offset gives everything needed to draw the chunk.

#include <array>
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

/// Sides of a chunk's square, in the order payload version 2 stores their skirt depths.
enum ChunkSideIndex : int { kSideSouth = 0, kSideEast = 1, kSideNorth = 2, kSideWest = 3 };

struct ChunkGeometry {
  double zBase = 0.0;
  double zStep = 1.0;
  /// Per side (ChunkSideIndex): how far its skirt hangs below the surface, in zStep units; 0
  /// where the side has none. What payload version 2 stores instead of the skirts (the encoder
  /// reads it only there; decoding version 1 leaves it 0).
  std::array<uint16_t, 4> skirtSteps{};
  std::vector<ChunkPart> parts;
};

/// How a blob's payload holds the skirts (docs/format.md "Chunk blobs").
enum class ChunkPayloadVersion : uint16_t {
  kStoredSkirts = 1,   ///< skirt vertices and triangles stored like the surface's
  kDerivedSkirts = 2,  ///< each side's depth stored; a reader derives the skirts
  kRtinCoded = 3,      ///< as 2, an RTIN chunk stored as its bintree (rtin_chunk_codec.h)
};

/// A surface edge along a skirted side, p -> q as its triangle winds (counter-clockwise seen
/// from above); `along` is the lower of its two coordinates along the side.
struct SkirtEdge {
  uint8_t side = 0;  ///< ChunkSideIndex
  uint16_t along = 0;
  uint32_t p = 0, q = 0;
};

/// The surface edges of `part` that skirts hang from under payload version 2: edges whose two
/// ends lie on the line of a side with skirtSteps > 0 (south y = 0, west x = 0, north
/// y = extentY, east x = extentX, where the extents are the largest x and y of the chunk's
/// vertices over all parts); triangles with all three corners on one line are skipped. Sorted
/// by side, then along.
std::vector<SkirtEdge> skirtEdges(const ChunkPart& part, const std::array<uint16_t, 4>& skirtSteps,
                                  uint16_t extentX, uint16_t extentY);

/// Appends to every part the skirts payload version 2 derives (docs/format.md "Derived skirts"):
/// per side, in order along it, a bottom vertex for every vertex of its edges (the top's x, y
/// and morph delta, z lowered by the side's steps), then two triangles per edge. Fails (with
/// what is wrong) when a bottom would fall below height 0, or a part would pass 65536 vertices
/// or 2^24 indices.
Status appendDerivedSkirts(ChunkGeometry& geometry);

/// Groups a chunk's triangles into parts of at most 65535 vertices, counting the skirt bottoms
/// a reader derives (`derivedSkirtSteps`; all 0 for stored skirts): one part when they fit,
/// else by the quadrant of the chunk's square (of `side` cells) each triangle's centroid lies
/// in, recursively. A part keeps its vertices in their order in `vertices` and its triangles
/// in theirs. Writers and the reader of payload version 3 both call it.
std::vector<ChunkPart> splitChunkParts(const std::vector<ChunkVertex>& vertices,
                                       std::vector<uint32_t> surface, std::vector<uint32_t> skirt,
                                       const std::array<uint16_t, 4>& derivedSkirtSteps,
                                       uint16_t side);

/// zstd level of chunk blobs unless a build asks for another (level 3 is within a few percent
/// of level 19 on chunk data, and an order of magnitude faster).
inline constexpr int kDefaultChunkCompressionLevel = 3;

/// Encodes; `compressionLevel` is zstd's level. Parts must have at most 65536 vertices. With
/// kDerivedSkirts the parts hold the surface only (surfaceIndexCount == indices.size(), no
/// skirt bottoms) and `skirtSteps` says where the skirts go.
std::vector<uint8_t> encodeChunk(const ChunkGeometry& geometry,
                                 int compressionLevel = kDefaultChunkCompressionLevel,
                                 ChunkPayloadVersion payload = ChunkPayloadVersion::kStoredSkirts);

/// Decodes and validates a blob (never trusts it); `subject` names it in errors.
Result<ChunkGeometry> decodeChunk(std::span<const uint8_t> blob, const std::string& subject);

/// Reorders a part's triangles for the post-transform vertex cache and its vertices for fetch
/// locality (meshoptimizer), keeping surface and skirt triangles in their own ranges.
void optimizeChunkPart(ChunkPart& part);

}  // namespace terralod
