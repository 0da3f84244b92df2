#pragma once
// Where each of a tile's layered depth images looks from (papers/tiling-layered-depth-images.md
// §4): 8 view directions around the tile, and 7 resolutions, one per ring of tiles around a
// head-height viewer. Each LDI is orthographic along the direction a viewer at that ring's
// distance and head height would look at the tile's centre, framed on the tile's bounding box.

#include <array>
#include <cstdint>

#include "terralod/vegetation/ldi.h"

namespace terralod::veg {

inline constexpr int kRings = 7, kDirections = 8;

/// The paper's resolutions, finest (nearest ring) first.
inline constexpr std::array<uint32_t, kRings> kPaperResolutions = {468, 232, 151, 111, 88, 73, 62};

struct LdiRig {
  float tileSize = 4;    ///< metres
  float tileHeight = 2;  ///< metres: top of the tallest plant
  float headHeight = 1.7f;
  std::array<uint32_t, kRings> resolutions = kPaperResolutions;
  std::array<float, kRings> ringDistances{};  ///< metres from the viewer to the tile centre
};

/// Ring distances by the paper's rule: one LDI pixel per screen pixel, so the distance scales
/// as 1/resolution, the finest ring one tile away.
std::array<float, kRings> ringDistancesFor(float tileSize,
                                           const std::array<uint32_t, kRings>& resolutions);

/// Scales the rig's resolutions so the finest is `finest` pixels (each at least 4) and sets
/// the ring distances by the same rule (quick bakes: tests, previews).
void scaleResolutions(LdiRig& rig, uint32_t finest);

/// Radians below the horizontal of a ray from the viewer's head to the tile centre's ground.
float ringElevation(const LdiRig& rig, int ring);

/// Azimuth of direction d (radians, clockwise from north): the viewer is on the side the
/// rays come from; direction 0 looks north (the viewer south of the tile), 2 looks east.
float directionAzimuth(int direction);

/// The camera of LDI (ring, direction) in the tile's frame.
LdiCamera ldiCamera(const LdiRig& rig, int ring, int direction);

/// The point of a depth pixel (column, row, quantized depth) in the tile's frame.
glm::vec3 ldiPoint(const LdiCamera& camera, uint32_t column, uint32_t row, uint32_t depth);

}  // namespace terralod::veg
