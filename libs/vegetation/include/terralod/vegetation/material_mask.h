#pragma once
// The material rule of `--vegetation-where material=A|B` resolved against a terrain's
// materials: one flag per cell of a grid over the terrain (the material map's grid, every k-th
// point when it is larger than kMaxMaterialMaskSide a side), set where the point's material is
// one of the named ones. A tile is allowed when the grid point nearest its centre is: the LDI
// tiles (vegetation_field.h) and the textures' pass (far_vegetation_layer.h, which gets the
// same grid as a texture) ask the same question, so they agree tile by tile.

#include <cstdint>
#include <string>
#include <vector>

#include "terralod/core/result.h"
#include "terralod/materials/material.h"

namespace terralod::veg {

/// The mask's grid is at most this many points a side (a texture the GL pass can hold).
inline constexpr int32_t kMaxMaterialMaskSide = 4096;

struct MaterialMask {
  int32_t columns = 0, rows = 0;
  double cellX = 1, cellY = 1;   ///< metres between grid points; point (0, 0) at the origin
  std::vector<uint8_t> allowed;  ///< south row first, `columns` per row: 1 allowed, 0 not

  /// Whether the grid point nearest (x, y) metres (clamped to the grid) is allowed.
  bool allowsAt(double x, double y) const;

  /// From `map` (grid points `spacingX` × `spacingY` metres apart) and the wanted material
  /// names (exact, as the map names them). Fails, naming `source`, when a name is not one of
  /// the map's ("--vegetation-where: material 'x' is not one of: rock, grass (in SOURCE)").
  static Result<MaterialMask> from(const MaterialMap& map, double spacingX, double spacingY,
                                   const std::vector<std::string>& names,
                                   const std::string& source);
};

}  // namespace terralod::veg
