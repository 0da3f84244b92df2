#include "terralod/materials/material.h"

#include <cassert>

namespace terralod {

uint8_t MaterialMap::at(int32_t x, int32_t y) const {
  assert(x >= 0 && x < columns && y >= 0 && y < rows);
  return classes[size_t(y) * size_t(columns) + size_t(x)];
}

}  // namespace terralod
