#pragma once
// An LDI seen from its own camera: each pixel's layers composited front to back over a
// background (what `terralod vegetation render-tile` writes).

#include <array>
#include <cstdint>
#include <vector>

#include "terralod/vegetation/ldi.h"

namespace terralod::veg {

/// RGBA, 4 bytes a pixel, top row first (as terralod::Image).
struct LdiPicture {
  int width = 0, height = 0;
  std::vector<uint8_t> rgba;
};

/// Layers composited with their alpha ("over", nearest first) over an opaque `background`.
LdiPicture compositeLdi(const Ldi& ldi, std::array<uint8_t, 3> background);

}  // namespace terralod::veg
