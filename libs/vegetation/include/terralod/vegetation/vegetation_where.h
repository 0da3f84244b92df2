#pragma once
// Where vegetation tiles are laid (`--vegetation-where`, issue 23): a comma-separated
// conjunction of terms, e.g. `height<2400,slope<30,material=grass|meadow`:
//   height<H, height>H   metres (the paper laid tiles below a height)
//   slope<S, slope>S     degrees from horizontal
//   material=A|B…        any of the named materials (the VIPM kind's, or a categorical raster's)
// A term may appear once. Parsing checks the syntax only; the material names against a
// tileset's are the caller's to check.

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "terralod/core/result.h"

namespace terralod::veg {

struct VegetationWhere {
  std::optional<double> heightBelow, heightAbove;  ///< metres
  std::optional<double> slopeBelow, slopeAbove;    ///< degrees
  std::vector<std::string> materials;              ///< any of these; empty: any material

  /// Whether a tile whose ground has this height, slope and material gets vegetation.
  bool allows(double height, double slopeDegrees, std::string_view material) const;
};

/// Errors name the option and the term: "--vegetation-where: 'slope<abc': not a number".
Result<VegetationWhere> parseVegetationWhere(std::string_view text);

}  // namespace terralod::veg
