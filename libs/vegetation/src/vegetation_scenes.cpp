#include "terralod/vegetation/vegetation_scenes.h"

#include <cmath>

namespace terralod::veg {

const std::vector<std::string>& vegetationSceneNames() {
  static const std::vector<std::string> names = {"sunflowers", "meadow"};
  return names;
}

Result<VegetationScene> vegetationScene(std::string_view name, std::optional<float> tileSize,
                                        uint64_t seed) {
  VegetationScene s;
  s.name = std::string(name);
  if (name == "sunflowers") {
    // Sunflowers packed a little apart (their leaves may touch, their heads not), ~20 a tile.
    s.placement.tileSize = 4.4f;
    s.placement.mix = {{Species::kSunflower, 1, 1.15f, 0.9f, 1.1f}};
    s.rig.headHeight = 1.7f;
  } else if (name == "meadow") {
    // Mostly grass, dandelions and small yellow flowers between the clumps.
    s.placement.tileSize = 2.0f;
    s.placement.mix = {{Species::kGrass, 6, 1.05f, 0.6f, 1.0f},
                       {Species::kDandelion, 1, 1.3f, 0.85f, 1.15f},
                       {Species::kYellowFlower, 2, 1.25f, 0.8f, 1.2f}};
    s.rig.headHeight = 1.7f;
    s.lighting.occlusionDistance = 0.3f;
  } else {
    std::string known;
    for (const std::string& n : vegetationSceneNames()) known += (known.empty() ? "" : ", ") + n;
    return makeError("--scene", "unknown scene '" + std::string(name) + "' (known: " + known + ")");
  }
  if (tileSize) {
    if (!std::isfinite(*tileSize) || *tileSize < 0.5f || *tileSize > 50.0f)
      return makeError("--tile-size", "must be between 0.5 and 50 metres");
    s.placement.tileSize = *tileSize;
  }
  s.placement.seed = seed;
  s.sampling.seed = seed;
  s.rig.tileSize = s.placement.tileSize;
  s.rig.ringDistances = ringDistancesFor(s.rig.tileSize, s.rig.resolutions);
  return s;
}

}  // namespace terralod::veg
