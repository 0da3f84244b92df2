#include "terralod/vegetation/plant_library.h"

namespace terralod::veg {

PlantLibrary::PlantLibrary(uint64_t seed) {
  for (int s = 0; s < kSpeciesCount; ++s)
    for (int v = 0; v < versionCount(Species(s)); ++v)
      mMeshes[s].push_back(makePlant(Species(s), v, seed));
}

}  // namespace terralod::veg
