#pragma once
// What stands in a vegetation tile: the prototiles' edge colours and their placed plants.

#include <array>
#include <cstdint>
#include <vector>

#include "terralod/vegetation/species.h"

namespace terralod::veg {

/// Edge colours of a Wang prototile (0 or 1 each). North and south edges share one pair of
/// colours, east and west the other.
struct TileEdges {
  uint8_t north = 0, east = 0, south = 0, west = 0;
  bool operator==(const TileEdges&) const = default;
};

/// One plant in a prototile, in the tile's frame: the tile is [0, size]², +z up. An object
/// whose tight disk crosses an edge is stored in every prototile it reaches, so x or y may lie
/// outside [0, size) (its centre is in the neighbour; only the part inside is drawn).
struct PlacedObject {
  float x = 0, y = 0;
  float tightRadius = 0;    ///< bounds the plant's geometry (horizontally)
  float packingRadius = 0;  ///< ≥ tightRadius: spacing between plants
  Species species = Species::kSunflower;
  uint8_t version = 0;
  float rotation = 0;  ///< radians about +z
  float scale = 1;     ///< applied to the model before placing
  bool operator==(const PlacedObject&) const = default;
};

struct PrototileContent {
  TileEdges edges;
  std::vector<PlacedObject> objects;
  bool operator==(const PrototileContent&) const = default;
};

}  // namespace terralod::veg
