#pragma once
// The collapse order of one chunk's progressive mesh (Hoppe's VIPM with half-edge collapses,
// as Alexandrov's terrain story uses it): starting from the full grid triangulation, repeatedly
// move one vertex onto a neighbour (no new positions), the one that changes the surface least,
// until no collapse is allowed.
//
// Allowed collapses v -> u:
//   - geometry: u shares an edge with v; the chunk's corners never move; a vertex on a chunk
//     side moves only along that side (so a chunk's border stays on its square, and each side
//     is a simplification of its samples); the mesh stays a manifold (link condition) and no
//     triangle turns over or degenerates seen from above.
//   - materials (MaterialRules::kOn, the paper's three rules):
//       1. v and u have the same material (no edge between materials collapses);
//       2. a vertex on a material boundary (with a neighbour of another material) moves only
//          onto another boundary vertex;
//       3. the interpolated material at v's position is v's own after the collapse (every
//          corner of the triangle that then covers it, with a non-zero weight there, is of
//          v's material).
//
// Error: the largest vertical distance between any source sample of the chunk and the mesh
// after the collapse, made monotone along the order (the running maximum). The next collapse
// is the allowed one whose new triangles lie closest to the samples they cover; ties go to the
// lower vertex id, so the order is deterministic.

#include <array>
#include <cstdint>
#include <vector>

#include "terralod/vipm/grid_patch.h"

namespace terralod {

enum class MaterialRules : uint8_t {
  kOn,  ///< the three rules above
  kOff  ///< geometry only (shows what the rules buy: material boundaries that move)
};

/// One half-edge collapse: `vertex` moves onto `target` (point ids of the patch).
struct Collapse {
  uint16_t vertex = 0;
  uint16_t target = 0;
  float error = 0.0f;  ///< metres; non-decreasing along the order
};

struct CollapseOrder {
  /// The triangulation the order starts from: unless CollapseStart gives one, the full grid's,
  /// two triangles per cell, the cell's diagonal alternating in a checkerboard ((x + y) even:
  /// south-west to north-east), counter-clockwise seen from above.
  std::vector<std::array<uint16_t, 3>> gridTriangles;
  std::vector<Collapse> collapses;
  /// A given start's own error (metres, rounded up); 0 for the full grid.
  float startError = 0.0f;
};

/// The grid triangulation described above.
std::vector<std::array<uint16_t, 3>> gridTriangulation(int32_t width, int32_t height);

/// Where an order starts, for meshes that are not a leaf's full grid (the first step to the
/// far field, docs/architecture.md Known gaps: a fallback root simplified further, starting
/// from its children's coarsest levels joined).
struct CollapseStart {
  /// The mesh to start from: triangles over patch points, counter-clockwise seen from above,
  /// a manifold whose only open edges lie on the patch's sides or seams. Empty: the full grid
  /// triangulation. Points no triangle uses are not part of the mesh.
  std::vector<std::array<uint16_t, 3>> triangles;
  /// Lines inside the patch (x = seamX, y = seamY; -1: none) whose vertices move only along
  /// them, as a side's do; where a seam meets a side or the other seam the vertex is locked.
  int32_t seamX = -1, seamY = -1;
};

/// Greedy collapse order of `patch` until no collapse is allowed, from `start`. Pure and
/// deterministic. The errors start at the starting mesh's own error.
CollapseOrder buildCollapseOrder(const GridPatch& patch, MaterialRules rules,
                                 const CollapseStart& start = {});

}  // namespace terralod
