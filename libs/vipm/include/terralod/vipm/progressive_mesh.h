#pragma once
// A chunk's view-independent progressive mesh as stored and drawn: one vertex buffer and one
// triangle list that serve every level of detail.
//
//   - Vertices are ordered so that the ones removed first come last: after j collapses the
//     active vertices are exactly [0, N - j). Runtime collapse j moves vertex N - 1 - j onto
//     targets[j] (a smaller index).
//   - Triangles are the finest level's, ordered by when they disappear, the ones that never do
//     first: after j collapses the living triangles are a prefix.
//   - errors[j] is the error after collapse j (see collapse_order.h), non-decreasing.
//
// The finest level is the collapse order with every collapse of error <= maxError already
// applied (so the stored mesh starts at maxError); the coarsest is the end of the order.

#include <array>
#include <cstdint>
#include <vector>

#include "terralod/core/result.h"
#include "terralod/vipm/collapse_order.h"
#include "terralod/vipm/grid_patch.h"

namespace terralod {

struct ProgressiveMesh {
  int32_t width = 0, height = 0;  ///< the patch's points along x and y
  /// Per vertex: its grid point (y * width + x), vertex order as above.
  std::vector<uint32_t> points;
  /// Per vertex: the patch point it was made from (makeProgressiveMesh; the grid point for a
  /// dense patch); empty in a mesh read back from a blob.
  std::vector<uint16_t> patchIds;
  std::vector<uint16_t> targets;  ///< per runtime collapse: the vertex it moves onto
  std::vector<float> errors;      ///< per runtime collapse: metres, non-decreasing
  /// The finest level's triangles (vertex indices, counter-clockwise from above), ordered by
  /// when they disappear, last first.
  std::vector<std::array<uint16_t, 3>> triangles;
  float finestError = 0.0f;  ///< error of the finest level (<= the build's maxError)

  uint32_t vertexCount() const { return uint32_t(points.size()); }
  uint32_t collapseCount() const { return uint32_t(targets.size()); }
  /// Vertices left after every collapse (the coarsest level).
  uint32_t coarsestVertexCount() const { return vertexCount() - collapseCount(); }
};

/// The progressive mesh of `order` starting at `maxError`.
ProgressiveMesh makeProgressiveMesh(const GridPatch& patch, const CollapseOrder& order,
                                    double maxError);

/// For each triangle of `mesh`, the runtime collapse that removes it (collapseCount() when
/// none does), replaying the collapses; fails if the mesh is inconsistent (a collapse whose
/// target is not a neighbour, a triangle order that is not by removal, ...).
Result<std::vector<uint32_t>> triangleRemovals(const ProgressiveMesh& mesh);

}  // namespace terralod
