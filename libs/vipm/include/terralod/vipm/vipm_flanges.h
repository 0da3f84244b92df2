#pragma once
// Flanges (skirts) of a VIPM chunk: every border vertex gets a copy hanging below it, and the
// border polyline of the level drawn now is closed down to the copies, so a neighbour at any
// level leaves no crack (the flange depth, the node's maxSkirtDepth, covers every neighbour's
// border deviation). Border vertices collapse only along their side and corners never do, so
// a side's active vertices in order along it are that level's border polyline.

#include <array>
#include <cstdint>
#include <vector>

#include "terralod/vipm/progressive_mesh.h"

namespace terralod {

/// Sides of a chunk, as bits of a mask.
enum FlangeSide : uint8_t {
  kFlangeWest = 1,
  kFlangeEast = 2,
  kFlangeSouth = 4,
  kFlangeNorth = 8,
  kFlangeAllSides = 15
};

struct Flanges {
  /// Per flange vertex k (drawn as vertex vertexCount + k): the border vertex it hangs from.
  std::vector<uint16_t> tops;
  /// Per side with a flange: its border vertices in order along it, as indices into `tops`.
  std::vector<std::vector<uint16_t>> sides;
};

/// The flanges of the sides in `sideMask` (FlangeSide bits).
Flanges makeFlanges(const ProgressiveMesh& mesh, uint8_t sideMask);

/// The flange triangles (two per border edge between active vertices, i.e. vertices <
/// `activeVertices`) for a mesh of `vertexCount` vertices; flange vertex k is vertexCount + k.
void flangeIndices(const Flanges& flanges, uint32_t vertexCount, uint32_t activeVertices,
                   std::vector<uint16_t>& out);

}  // namespace terralod
