#pragma once
// Every version of every species' model for one seed, made once and shared read-only.

#include <array>
#include <cstdint>
#include <vector>

#include "terralod/vegetation/plant_models.h"

namespace terralod::veg {

class PlantLibrary {
 public:
  explicit PlantLibrary(uint64_t seed);
  /// Given models (tests: analytic shapes), one list per species.
  explicit PlantLibrary(std::array<std::vector<PlantMesh>, kSpeciesCount> meshes)
      : mMeshes(std::move(meshes)) {}
  const PlantMesh& mesh(Species s, int version) const { return mMeshes[size_t(s)][version]; }
  float tightRadius(Species s, int version) const { return mesh(s, version).tightRadius; }

 private:
  std::array<std::vector<PlantMesh>, kSpeciesCount> mMeshes;
};

}  // namespace terralod::veg
