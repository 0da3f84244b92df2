#pragma once
// Vegetation beyond the LDI range as directional textures draped on the terrain
// (papers/tiling-layered-depth-images.md §8, "future work"): for each prototile, each of the 8
// view directions and a few elevations of the line of sight, what a viewer far away sees at
// each ground point of the tile: the tile in a 3×3 context warped from its LDIs by an oblique
// projection along the line of sight onto the ground, so a plant's picture lands where the
// line of sight through it meets the ground (plants of the neighbours included). Made when a
// .tlv is opened, from the LDIs themselves: no geometry, no ray tracing.

#include <array>
#include <cstdint>
#include <vector>

#include "terralod/core/result.h"
#include "terralod/vegetation/vegetation_file.h"

namespace terralod::veg {

/// Elevations (degrees below the horizontal) of the lines of sight the textures are made for.
inline constexpr std::array<float, 4> kTextureElevations = {3.0f, 8.0f, 20.0f, 45.0f};
inline constexpr int kTextureElevationCount = int(kTextureElevations.size());

struct DirectionalTextures {
  int size = 0;  ///< texels across a tile
  /// Premultiplied RGBA8 (red in the low byte), `size`² each, row 0 at the tile's north edge;
  /// texture (prototile, direction, elevation) at index textureIndex().
  std::vector<uint32_t> rgba;
  static constexpr int textureIndex(int prototile, int direction, int elevation) {
    return (prototile * kLdiDirections + direction) * kTextureElevationCount + elevation;
  }
  static constexpr int kCount = kPrototiles * kLdiDirections * kTextureElevationCount;
};

/// Texels across a tile unless asked otherwise (the paper suggests 32).
inline constexpr int kDirectionalTextureSize = 32;

/// Warps each texture's context from the LDIs of the ring whose elevation is nearest (reading
/// them from `file`); fails on the first unreadable LDI.
Result<DirectionalTextures> makeDirectionalTextures(const VegetationReader& file,
                                                    int size = kDirectionalTextureSize);

}  // namespace terralod::veg
