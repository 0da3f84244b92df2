#pragma once
// Placing a tile on the terrain (papers/tiling-layered-depth-images.md §5.4): the tile is cut
// along its diagonal from the south-west to the north-east corner into two triangles, and each
// half is sheared affinely onto the terrain triangle over it: (x, y, z) ↦ (x₀ + x, y₀ + y,
// z + h(x, y)), h the plane through that triangle's three corner heights. The halves agree on
// the diagonal, so nothing parts there; the vertical plane through the diagonal orders them
// (the half on the far side from the eye first).

#include <array>

#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

namespace terralod::veg {

/// South-east of the diagonal (x ≥ y in the tile frame) or north-west of it.
enum class TileHalf { kSouthEast, kNorthWest };

inline TileHalf halfOf(float x, float y) {
  return x >= y ? TileHalf::kSouthEast : TileHalf::kNorthWest;
}

struct TileOnTerrain {
  glm::vec2 origin{0};             ///< world position of the tile's south-west corner
  float size = 1;                  ///< metres
  std::array<float, 4> heights{};  ///< terrain heights at the SW, SE, NE, NW corners
};

/// The tile-frame → world matrix of one half.
glm::mat4 halfShear(const TileOnTerrain& tile, TileHalf half);

/// The half to draw first for an eye at `eye` (world): the one on the other side of the
/// diagonal's vertical plane.
TileHalf farHalf(const TileOnTerrain& tile, const glm::vec3& eye);

}  // namespace terralod::veg
