#pragma once
// Flanges (skirts) of a VIPM chunk: every border vertex gets a copy hanging below it, and the
// border polyline of the level drawn now is closed down to the copies, so a neighbour at any
// level leaves no crack (the flange depth, the node's maxSkirtDepth, covers every neighbour's
// border deviation). Border vertices collapse only along their side and corners never do, so
// a side's active vertices in order along it are that level's border polyline.

#include <array>
#include <cstdint>
#include <span>
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
  /// Interior grid lines (see makeFlanges): per vertex, its flange (an index into `tops`)
  /// and the lines it lies on (x, y; -1: none), or empty when the chunk has no such lines.
  struct OnLine {
    int32_t flange = -1;
    int16_t lineX = -1, lineY = -1;
  };
  std::vector<OnLine> interior;
  /// The most interior flange edges a level has: its finest level's (collapses along a line
  /// only ever join its edges).
  uint32_t interiorEdgesMax = 0;
};

/// The flanges of the sides in `sideMask` (FlangeSide bits). With `interiorStep` > 0, also
/// under every edge of the drawn level that lies on an interior grid line x or y = k ·
/// interiorStep: a root joins its children's coarsest levels, whose shared sides need not
/// match (T-junctions), and simplifies each side's vertices along those lines only, so each
/// side's edges there get a flange and close the gap at every level.
Flanges makeFlanges(const ProgressiveMesh& mesh, uint8_t sideMask, int32_t interiorStep = 0);

/// The flange triangles for a mesh of `vertexCount` vertices (flange vertex k is vertexCount +
/// k): two per border edge between active vertices (vertices < `activeVertices`), and two per
/// edge on an interior line of the triangles drawn now, `living` (the whole chunk's indices).
void flangeIndices(const Flanges& flanges, uint32_t vertexCount, uint32_t activeVertices,
                   std::span<const uint16_t> living, std::vector<uint16_t>& out);

/// The most flange indices flangeIndices gives at any level.
size_t maxFlangeIndices(const Flanges& flanges);

}  // namespace terralod
