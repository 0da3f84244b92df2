#pragma once
// A VIPM chunk's normal map, computed at load from its stored heights (normals come from
// textures, never from the drawn mesh, so lighting does not move when the level changes).

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "terralod/vipm/progressive_mesh.h"

namespace terralod {

/// The height of every grid point (row-major, south row first, width x height) on the finest
/// level of `mesh`, whose vertices are at `positions` (grid x, grid y, height): stored
/// vertices keep their height, the other points take the plane of the triangle over them.
std::vector<float> finestGridHeights(const ProgressiveMesh& mesh,
                                     std::span<const std::array<float, 3>> positions);

/// Per grid point two bytes: the unit normal's x and y as round((c + 1) / 2 · 255) (z =
/// sqrt(1 − x² − y²), upwards). Slopes by central differences over `spacing` metres per cell,
/// one-sided on the chunk's edges.
std::vector<uint8_t> normalMap(std::span<const float> heights, int32_t width, int32_t height,
                               std::array<double, 2> spacing);

}  // namespace terralod
