#pragma once
// Poisson-disk placement of plants in the 8 Wang prototiles, consistent across edges
// (papers/tiling-layered-depth-images.md §3, Figures 5–6).
//
// The edges are filled first (crossing plants must find room in every prototile with the
// edge's colour, which filled tiles rarely offer: thrown among the rest they would stay few
// and each tile edge would show as a sparse line), each edge colour up to 80 % of the plants a
// plain placement has along a line (more would pack a denser line than the field); then the
// corners, likewise hard to fill late. Then dart throwing visits the prototiles round-robin,
// up to `attemptsPerVisit` darts a visit (of one species, picked by the mix's weights), and
// keeps the first that fits; a tile is done when no species finds room. Each plant has a tight
// radius (its geometry) and a larger packing radius (its spacing). A plant whose tight disk crosses
// an edge of colour c belongs to that edge: it is stored in every prototile with colour c on that
// side and, shifted by a tile, in every prototile with colour c on the opposite side, so whichever
// prototile lands across the edge continues it. A dart is tested (packing radii) against the plants
// of every prototile it would be stored in and of every prototile that can lie across an edge its
// packing disk reaches. No tight disk crosses two edge lines (so none reaches across a
// corner); packing disks may (the paper's buffer crossing corners): two plants in
// diagonally adjacent tiles are kept apart by their tight radii only.

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "terralod/core/progress.h"
#include "terralod/vegetation/tile_objects.h"

namespace terralod::veg {

/// One kind of plant in a scene's mix.
struct SpeciesMix {
  Species species = Species::kSunflower;
  double weight = 1;           ///< relative frequency of visits for this species
  float packingFactor = 1.2f;  ///< packing radius = tight radius × this (≥ 1)
  float minScale = 0.9f, maxScale = 1.1f;
};

struct PlacementSettings {
  float tileSize = 4;
  std::vector<SpeciesMix> mix;  ///< at most 32
  uint32_t attemptsPerVisit = 10000;
  /// Fill the edges, then the corners, before the rest (below); off: the paper's plain
  /// round-robin over the prototiles (the switch that shows what the order does).
  bool edgesAndCornersFirst = true;
  uint64_t seed = 1;
};

/// The tight radius of a species' version at scale 1 (its model's tightRadius).
using TightRadiusOf = std::function<float(Species, int version)>;

struct Placement {
  std::vector<PrototileContent> tiles;  ///< 8, edges as prototileEdges(k)
};

Placement placeObjects(const PlacementSettings& settings, const TightRadiusOf& tightRadius,
                       Progress& progress);

/// Whether an object's centre lies in its tile's square [0, size)²: each plant of a tiling
/// is drawn in full by the tile its centre is in, and by its neighbours in part.
inline bool centredIn(const PlacedObject& o, float size) {
  return o.x >= 0 && o.x < size && o.y >= 0 && o.y < size;
}

}  // namespace terralod::veg
