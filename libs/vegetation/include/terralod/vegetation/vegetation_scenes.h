#pragma once
// The two scenes of the paper (§6): `sunflowers` (about 20 sunflowers a tile) and `meadow`
// (grass clumps, dandelions and small yellow flowers): what grows, how it is spaced, and how
// its LDIs are sampled and lit.

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "terralod/core/result.h"
#include "terralod/vegetation/bake_settings.h"
#include "terralod/vegetation/ldi_camera.h"
#include "terralod/vegetation/tile_placement.h"

namespace terralod::veg {

struct VegetationScene {
  std::string name;
  PlacementSettings placement;
  LdiRig rig;  ///< tileHeight is set from the placed plants by the baker
  Lighting lighting;
  SamplingSettings sampling;
};

/// The names `vegetationScene` knows, for help texts and errors.
const std::vector<std::string>& vegetationSceneNames();

/// A scene by name; `tileSize` overrides its tile size (metres, 0.5–50), `seed` varies the
/// plants' models and their placement. Errors name the bad value.
Result<VegetationScene> vegetationScene(std::string_view name, std::optional<float> tileSize,
                                        uint64_t seed);

}  // namespace terralod::veg
