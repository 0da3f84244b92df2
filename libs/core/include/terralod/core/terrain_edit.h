#pragma once
// One brush stroke on a VIPM tileset's terrain (`terralod edit --script`, the `view` brush):
// what it does, where, how far and how much. The JSON form is docs/format.md "Edits"
// (terralod/format/terrain_edits_json.h); applying it to heights and materials is
// terralod/materials/terrain_edits.h.

#include <cstdint>
#include <string_view>

namespace terralod {

enum class Brush : uint8_t {
  kRaise,   ///< heights go up by `amount` metres at the centre, less toward the rim
  kLower,   ///< heights go down likewise
  kSmooth,  ///< heights move toward their 3 x 3 neighbourhood's mean, by `amount` in (0, 1]
  kPaint    ///< grid points within the radius take `material`
};

struct TerrainEdit {
  Brush brush = Brush::kRaise;
  /// Metres east and north of the data's south-west sample (the tileset's x and y, as
  /// `terralod info` prints the extent).
  double centerX = 0.0, centerY = 0.0;
  double radius = 0.0;   ///< metres, > 0
  double amount = 0.0;   ///< raise and lower: metres; smooth: strength in (0, 1]; paint: unused
  uint8_t material = 0;  ///< paint: the material's id (as the tileset's "materials" list it)
  friend bool operator==(const TerrainEdit&, const TerrainEdit&) = default;
};

/// "raise", "lower", "smooth" or "paint".
constexpr std::string_view brushName(Brush brush) {
  switch (brush) {
    case Brush::kRaise:
      return "raise";
    case Brush::kLower:
      return "lower";
    case Brush::kSmooth:
      return "smooth";
    case Brush::kPaint:
      return "paint";
  }
  return "?";
}

}  // namespace terralod
