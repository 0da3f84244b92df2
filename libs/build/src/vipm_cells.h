#pragma once
// The VIPM chunk sides (tileset_format.h) as signed grid cells, for grid arithmetic.

#include <cstdint>

#include "terralod/format/tileset_format.h"

namespace terralod {

inline constexpr int32_t kLeaf = int32_t(kVipmLeafCells);
inline constexpr int32_t kRoot = int32_t(kVipmRootCells);

}  // namespace terralod
