#pragma once
// Chunk payload version 3 (format version 7): an RTIN chunk stored as what makes it instead of
// its vertex and index lists. The triangles are the leaves of the chunk's bintree, so one
// decision per splittable triangle visited gives them all, and the vertices' grid positions and
// order with them; a height is stored as its difference from the mean of its split's two
// hypotenuse ends, a morph delta as its difference from the same mean of their morph targets
// (the parent's surface is linear along the hypotenuse when the parent does not split there).
// Decisions and residuals are range-coded in contexts (range_coder.h). A reader walks the
// bintree as the mesher did and gets exactly the vertices, triangles and parts that payload
// version 2 stores (docs/format.md "Version 7").

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "terralod/core/result.h"
#include "terralod/format/chunk_codec.h"

namespace terralod {

/// What the mesher decided at one splittable triangle of its walk (bits of a byte).
enum RtinDecision : uint8_t {
  kRtinSplit = 1,         ///< the triangle is split at this level
  kRtinParentSplits = 2,  ///< the parent level splits it too (its midpoint is a parent vertex)
  kRtinInParent = 4,      ///< the triangle is one of the parent level's bintree
};

/// One RTIN chunk as the mesher made it, in the chunk's own grid coordinates.
struct RtinChunkInput {
  int sideLog2 = 0;               ///< the chunk's square is 2^sideLog2 cells on a side
  bool rising = true;             ///< cut along "/" (squareHasRisingDiagonal of the square)
  uint16_t clipX = 0, clipY = 0;  ///< the data inside the square: min(side, cells - origin)
  bool hasParent = false;         ///< level > 0
  double zStep = 1.0;
  int32_t zBaseSteps = 0;
  std::array<uint16_t, 4> skirtSteps{};
  std::span<const uint8_t> decisions;     ///< RtinDecision bits, one per splittable triangle
  std::span<const ChunkVertex> vertices;  ///< the surface's vertices, in the mesher's order
  std::span<const uint32_t> indices;      ///< the surface's triangles
};

/// Encodes payload version 3; nothing when walking `decisions` does not give exactly
/// `vertices` and `indices` (the caller then stores payload version 2). The coded bytes do not
/// compress: the blob's zstd frame is written at level 1 whatever the build's level.
std::optional<std::vector<uint8_t>> encodeRtinChunk(const RtinChunkInput& chunk);

/// Decodes a payload version 3 (after its zstd frame): the geometry payload version 2 of the
/// same chunk decodes to. `subject` names the blob in errors.
Result<ChunkGeometry> decodeRtinPayload(std::span<const uint8_t> raw, const std::string& subject);

}  // namespace terralod
