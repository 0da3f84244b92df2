#pragma once
// A VIPM chunk as the loader threads decode it (no GL): the stored blob decoded, unpacked and
// reconstructed into index parts (libs/vipm), its normal map from the stored heights, its
// flanges, and the vertices as the GPU takes them.

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "terralod/core/result.h"
#include "terralod/runtime/residency.h"
#include "terralod/vipm/progressive_mesh.h"
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
  Flanges flanges;
  float flangeDepth = 0.0f;
  double zBase = 0.0;
  int32_t width = 0, height = 0;  ///< grid points
  std::vector<uint8_t> normals;   ///< RG8 per grid point (vipm_normal_map.h)

  uint64_t bytes() const;
};

/// Decodes a VIPM blob (`subject` names it in errors) into a payload. `spacing`: metres per
/// cell; `flangeSides`: FlangeSide bits of the sides that get flanges, `flangeDepth` metres.
Result<VipmChunkPayload> decodeVipmPayload(std::span<const uint8_t> blob,
                                           const std::string& subject,
                                           std::array<double, 2> spacing, uint8_t flangeSides,
                                           float flangeDepth);

}  // namespace terralod
