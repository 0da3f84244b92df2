#pragma once
// A VIPM chunk as the loader threads decode it (no GL): the stored blob decoded, unpacked and
// reconstructed into index parts (libs/vipm), its stored normal map (BC5, made from the
// source heights at build time), its flanges, and the vertices as the GPU takes them.

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "terralod/core/result.h"
#include "terralod/format/node_bytes.h"
#include "terralod/format/texture_codec.h"
#include "terralod/runtime/residency.h"
#include "terralod/vipm/progressive_mesh.h"
#include "terralod/vipm/vipm_blot.h"
#include "terralod/vipm/vipm_fans.h"
#include "terralod/vipm/vipm_flanges.h"
#include "terralod/vipm/vipm_levels.h"

namespace terralod {

struct VipmChunkPayload final : ChunkPayload {
  ProgressiveMesh mesh;  ///< collapse targets and errors, for the geomorph
  VipmLevels levels;     ///< at the finest level
  /// Per vertex, then per flange vertex: grid x, grid y, metres above zBase (own positions;
  /// a flange vertex lies flangeDepth below its top).
  std::vector<std::array<float, 3>> positions;
  std::vector<uint8_t> materials;  ///< per vertex, then per flange vertex (its top's)
  MaterialFade fade = MaterialFade::kKeep;
  Flanges flanges;
  float flangeDepth = 0.0f;
  /// Its fan stitching state, with where it lies (its corner in grid cells).
  VipmStitcher stitcher;
  double zBase = 0.0;
  int32_t width = 0, height = 0;  ///< grid points
  uint32_t cells = 0;             ///< the node's side in cells (unclipped)
  /// The node's normal map: vipmNormalMapCells(cells) + 1 texels a side over its unclipped
  /// square, texel i on grid point i times cells / that (docs/format.md "VIPM tilesets").
  TextureLayer normals;
  /// Its blot texture (vipm_blot.h): encoded RGBA bytes, texels as the normal map's.
  std::vector<uint8_t> blot;

  /// Everything it holds (what a chunk costs between its load and its upload).
  uint64_t bytes() const;
  /// Of those, the texture bytes (normal map and blot), which go to the GPU and are not kept.
  uint64_t textureBytes() const;
};

/// Decodes a VIPM node's bytes (its blob and its texture blob; `subject` names it in errors)
/// into a payload. `chunkCells`: the node's side in cells (its normal map has one more texel);
/// `flangeSides`: FlangeSide bits of the sides that get flanges, `flangeDepth` metres;
/// `cornerX`, `cornerY`: the node's south-west grid point; `largestCells`: the tileset's top
/// node's side (StitchChunk); `averages`: the materials' average colours, for its blot
/// texture.
Result<VipmChunkPayload> decodeVipmPayload(const NodeBytes& node, const std::string& subject,
                                           uint32_t chunkCells, uint8_t flangeSides,
                                           float flangeDepth, int64_t cornerX, int64_t cornerY,
                                           uint32_t largestCells, const MaterialAverages& averages);

}  // namespace terralod
