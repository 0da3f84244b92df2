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
  /// Edges of the finest level on interior grid lines (pairs of indices into `tops`), each
  /// with a flange under it whatever the level: see makeFlanges.
  std::vector<std::array<uint16_t, 2>> interior;
};

/// The flanges of the sides in `sideMask` (FlangeSide bits). With `interiorStep` > 0, also
/// under every edge of the finest level that lies on an interior grid line x or y = k ·
/// interiorStep: a fallback root joins its children's coarsest levels, whose shared sides need
/// not match (T-junctions), so each side's edges there get a flange and close the gap. Meant
/// for meshes without collapses (their finest level is the only one).
Flanges makeFlanges(const ProgressiveMesh& mesh, uint8_t sideMask, int32_t interiorStep = 0);

/// The flange triangles (two per border edge between active vertices, i.e. vertices <
/// `activeVertices`) for a mesh of `vertexCount` vertices; flange vertex k is vertexCount + k.
void flangeIndices(const Flanges& flanges, uint32_t vertexCount, uint32_t activeVertices,
                   std::vector<uint16_t>& out);

}  // namespace terralod
