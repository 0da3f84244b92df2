#pragma once
// A generated detail texture per material, for texture splatting: deterministic, tileable
// (periodic noise whose lattice periods divide the size, so it wraps seamlessly both ways),
// and with the material's colour as its mean (within 2/255 per channel).
//
// The pattern follows the material's name (case-insensitive substrings):
//   water/lake/sea/river/ocean       smooth ripples (two periodic waves bent by noise), low
//   contrast rock/stone/cliff/scree/boulder   high contrast: strata bent by noise and dark cracks
//   grass/veg/forest/meadow/tree/... fine speckle over soft blotches, green varies most
//   snow/ice/glacier/firn            very low contrast, smooth
//   soil/sand/dirt/earth/mud/bare    medium blotches (a few octaves of noise)
//   anything else                    generic noise whose seed is the material's id
// Generation starts from the colour plus the pattern, then shifts each channel so that the
// rounded bytes average to the colour; where clamping at 0 or 255 prevents that, the
// pattern's contrast is halved until it fits.

#include <cstdint>
#include <vector>

#include "terralod/materials/material.h"

namespace terralod {

struct DetailTexture {
  int size = 0;
  std::vector<uint8_t> rgb;  ///< size * size * 3 bytes, row 0 = south
};

/// `size` is a power of two (e.g. 256). About 2 ms for 256² on one core.
DetailTexture makeDetailTexture(const Material& material, int size);

}  // namespace terralod
