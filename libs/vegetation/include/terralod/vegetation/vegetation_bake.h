#pragma once
// The whole bake of a scene: plants made, placed in the 8 prototiles, each prototile set in
// its 3×3 context and its 448 LDIs cast, lit and encoded (`terralod vegetation bake`).

#include <vector>

#include "terralod/core/progress.h"
#include "terralod/vegetation/vegetation_file.h"
#include "terralod/vegetation/vegetation_scenes.h"

namespace terralod::veg {

struct VegetationBake {
  VegetationHeader header;
  std::vector<EncodedLdi> ldis;  ///< kLdiCount, ldiIndex order
};

/// Deterministic for a scene and any thread count: the same plants and LDIs (only the
/// recorded bake time differs).
VegetationBake bakeVegetation(const VegetationScene& scene, unsigned threads, Progress& progress);

}  // namespace terralod::veg
