#pragma once
// The air of the aerial perspective (terrain_shaders.h, kAtmosphere): an exponential
// atmosphere over a flat earth, density exp(-z / H) relative to sea level.

#include <algorithm>

#include "terralod/render/terrain_style.h"

namespace terralod {

/// H, metres: the height over which the air's density falls by a factor e.
inline constexpr double kScaleHeight = 8000.0;
/// Extinction of sea-level air per metre: Rayleigh scattering at 550 nm (about 1/86 km), so
/// a vertical ray through the whole column keeps 91% of what lies below it.
inline constexpr double kSeaLevelExtinction = 1.16e-5;

/// The extinction the shaders use: the sea-level value scaled by the style's haze.
inline double extinction(const TerrainStyle& style) {
  return kSeaLevelExtinction * std::max(style.haze, 0.0);
}

}  // namespace terralod
