#pragma once
// Class palettes: which raster value is which material, as a JSON file
//
//   {"classes": [{"value": 3, "name": "forest", "color": [34, 90, 40]},
//                {"value": 7, "name": "rock", "color": "#8a8580"}, ...]}
//
// `value` is a whole number 0..255, `name` a non-empty string, `color` three numbers 0..255
// or "#rrggbb". Values are unique; at least one class. Other keys are ignored.

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "terralod/core/result.h"
#include "terralod/materials/material.h"

namespace terralod {

/// Reads a palette file; the classes come back in file order (Material::id = value). Errors
/// name the file and say what does not match the schema above.
Result<std::vector<Material>> readPalette(const std::string& path);

/// A fixed list of distinct colours for classes nobody named: index i gives the i-th (cycling
/// after 12).
std::array<uint8_t, 3> distinctColor(size_t index);

}  // namespace terralod
