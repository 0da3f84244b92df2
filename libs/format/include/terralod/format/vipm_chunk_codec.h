#pragma once
// VIPM chunk blobs (MeshKind::kVipm): a chunk's progressive mesh in compact form, as
// docs/format.md "VIPM chunks" lays it out. The collapse order is the vertex order (the last
// vertices go first), so a collapse costs its target (2 bytes) and its quantised error
// (2 bytes); the finest level's triangles are stored in removal order with meshoptimizer's
// index codec. Index buffers for every level are rebuilt from this in O(n) (libs/vipm,
// VipmLevels::reconstruct). The whole payload is one zstd frame.

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "terralod/core/result.h"
#include "terralod/format/texture_codec.h"

namespace terralod {

/// Grid points a side of a version 1 VIPM blob at most: 65 for a leaf, 129 for a root (its four
/// children's coarsest levels joined).
inline constexpr uint32_t kVipmMaxGridPoints = 129;
/// Grid points a side of a version 2 blob at most: a node above the roots (upper levels of 256,
/// 512, ... cells, at most 32768).
inline constexpr uint32_t kVipmMaxUpperGridPoints = 32769;

struct VipmChunkData {
  /// The chunk's grid points along x and y: 2..129 (stored as version 1) or up to 32769
  /// (version 2, nodes above the roots).
  uint16_t width = 0, height = 0;
  double zBase = 0.0;  ///< height = zBase + z * zStep (metres)
  double zStep = 1.0;
  float errorStep = 1.0f;          ///< a collapse's error = its quantised error * errorStep
  float finestError = 0.0f;        ///< error of the finest level, metres
  std::vector<uint32_t> points;    ///< per vertex: grid point y * width + x
  std::vector<uint16_t> heights;   ///< per vertex: quantised height
  std::vector<uint8_t> materials;  ///< per vertex: material index, < 8
  std::vector<uint16_t> targets;   ///< per collapse j: the vertex that vertex N-1-j moves onto
  std::vector<uint16_t> errors;    ///< per collapse: quantised error, non-decreasing
  std::vector<uint16_t> indices;   ///< the finest level's triangles, by removal (last first)

  uint32_t vertexCount() const { return uint32_t(points.size()); }
  uint32_t collapseCount() const { return uint32_t(targets.size()); }
  uint32_t triangleCount() const { return uint32_t(indices.size() / 3); }
};

/// Whether `chunk` is stored as version 1 (both sides at most kVipmMaxGridPoints; the form
/// every leaf and root takes) or 2.
uint16_t vipmChunkVersion(const VipmChunkData& chunk);

/// Encodes; `compressionLevel` is zstd's.
std::vector<uint8_t> encodeVipmChunk(const VipmChunkData& chunk, int compressionLevel);

/// Decodes and validates a blob (never trusts it); `subject` names it in errors. The
/// collapse order's consistency with the triangles is checked when it is reconstructed.
Result<VipmChunkData> decodeVipmChunk(std::span<const uint8_t> blob, const std::string& subject);

/// The cells a VIPM node's normal map spans a side: its own up to 128 (one texel per grid
/// point), 128 above (one texel every chunkCells / 128 points).
inline uint32_t vipmNormalMapCells(uint32_t chunkCells) {
  return chunkCells < 128u ? chunkCells : 128u;
}

/// The texture blob of a VIPM node (docs/format.md "VIPM tilesets"): exactly one layer, a BC5
/// normal map of vipmNormalMapCells(`chunkCells`) + 1 texels a side over the node's unclipped
/// square, made from the source heights. Decodes and validates it;
/// `subject` names the chunk in errors ("<subject>: invalid texture: ...").
Result<TextureLayer> decodeVipmNormalMap(std::span<const uint8_t> texture, uint32_t chunkCells,
                                         const std::string& subject);

}  // namespace terralod
