#pragma once
// A material is one class of ground (water, grass, rock, or whatever a categorical raster
// names), and a MaterialMap gives the material of every DEM grid point.

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace terralod {

/// Splatting draws one pass per material, so a map holds at most this many.
constexpr int kMaxMaterials = 8;

struct Material {
  uint8_t id = 0;                  ///< the class value as the user knows it (raster value)
  std::string name;                ///< e.g. "rock", "forest", "class 3"
  std::array<uint8_t, 3> color{};  ///< average colour, sRGB
};

struct MaterialMap {
  int32_t columns = 0, rows = 0;
  /// One per DEM grid point in grid order: south row first (grid y = rows - 1 - raster row),
  /// `columns` per row. The value is an INDEX into `materials`.
  std::vector<uint8_t> classes;
  std::vector<Material> materials;  ///< at most kMaxMaterials

  /// The material index at grid point (x, y); asserts the point is inside.
  uint8_t at(int32_t x, int32_t y) const;
};

}  // namespace terralod
