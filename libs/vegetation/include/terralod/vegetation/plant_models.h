#pragma once
// Procedural plant models, made by the project (no downloaded assets): sunflowers, grass
// clumps, dandelions and small yellow flowers, each in a fixed number of versions
// (species.h). A model is a triangle soup with one sRGB colour per triangle, in metres, its
// stem's foot at the origin and +z up. The same (species, version, seed) always gives the
// same bytes, so a .tlv file stores only which model stands where, never the geometry.

#include <array>
#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

#include "terralod/vegetation/species.h"

namespace terralod::veg {

struct PlantMesh {
  std::vector<glm::vec3> positions;
  std::vector<std::array<uint32_t, 3>> triangles;
  std::vector<std::array<uint8_t, 3>> colors;  ///< one sRGB colour per triangle
  float tightRadius = 0;  ///< largest horizontal distance of any vertex from the z axis
  float height = 0;       ///< largest z of any vertex
};

/// Version `version` (0 ≤ version < versionCount(species)) of a species' model. `seed`
/// varies every version at once (another scene's plants); asserts on a bad version.
PlantMesh makePlant(Species species, int version, uint64_t seed);

}  // namespace terralod::veg
