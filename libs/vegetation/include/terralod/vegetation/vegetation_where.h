#pragma once
// Where vegetation tiles are laid (`--vegetation-where`, issue 23): a comma-separated
// conjunction of terms, e.g. `height<2400,slope<30,material=grass|meadow`:
//   height<H, height>H   metres (the paper laid tiles below a height)
//   slope<S, slope>S     degrees from horizontal
//   material=A|B…        any of the named materials (the VIPM kind's, or a categorical raster's)
// A term may appear once. Parsing checks the syntax only; the material names are resolved
// against a terrain's materials (tileset_materials.h) into a MaterialMask by the caller, and
// until then a material rule allows nothing.

#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <glm/vec2.hpp>

#include "terralod/core/result.h"
#include "terralod/vegetation/material_mask.h"

namespace terralod::veg {

struct VegetationWhere {
  std::optional<double> heightBelow, heightAbove;  ///< metres
  std::optional<double> slopeBelow, slopeAbove;    ///< degrees
  std::vector<std::string> materials;              ///< any of these; empty: any material
  /// `materials` resolved against the terrain's (null while unresolved, or without a material
  /// rule). Shared: the rule's copies in the layers all read one grid.
  std::shared_ptr<const MaterialMask> materialMask;

  /// Whether a tile whose ground has this height and slope and whose centre is at `centre`
  /// (metres from the terrain's south-west sample) gets vegetation: both of the below.
  bool allows(double height, double slopeDegrees, glm::dvec2 centre) const {
    return allowsMaterialAt(centre) && allowsGround(height, slopeDegrees);
  }
  /// The material term alone (true without one): needs no heights, so callers ask it first.
  bool allowsMaterialAt(glm::dvec2 centre) const;
  /// The height and slope terms alone.
  bool allowsGround(double height, double slopeDegrees) const;
};

/// Errors name the option and the term: "--vegetation-where: 'slope<abc': not a number".
Result<VegetationWhere> parseVegetationWhere(std::string_view text);

}  // namespace terralod::veg
