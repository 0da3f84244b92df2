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
//
// Geomorph spacing: at run time collapse j slides its vertex while the allowed error is in
// [errors[j], kMorphSpan errors[j]] (vipm_levels.h). Two collapses that slide at once and
// share a triangle can fold the surface mid-slide (triangles overlap) even though each alone
// slides inside its own fan. So a collapse made at run time holds back every vertex of its
// fan: their own collapses get an error of at least kMorphSpan times its error (a recorded
// error above the measured one, which keeps the bound), and the greedy order takes others
// first. Then no two sliding collapses touch, and every slide stays inside a fan that does not
// change while it slides.

#include <array>
#include <cstdint>
#include <limits>
#include <vector>

#include "terralod/vipm/grid_patch.h"

namespace terralod {

/// A runtime collapse geomorphs while the allowed error goes from its error to kMorphSpan
/// times it. Short, because the spacing holds a collapse's neighbours back by this factor (a
/// factor two made the climbs draw 2.7x (Crater Lake) and 12x (Zion) the triangles they drew
/// without the spacing, median), long enough to take about 45 frames of the auto flight's
/// 0.5 % steps.
inline constexpr double kMorphSpan = 1.25;

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

/// Whether collapses that touch are kept from geomorphing together (see above). kOff only
/// shows what the spacing buys: surfaces that fold mid-slide.
enum class GeomorphSpacing : uint8_t { kOn, kOff };

/// Where an order starts (for meshes that are not a leaf's full grid: a root simplified
/// further, starting from its children's coarsest levels joined) and what holds it back.
struct CollapseStart {
  /// The mesh to start from: triangles over patch points, counter-clockwise seen from above,
  /// a manifold whose only open edges lie on the patch's sides or seams. Empty: the full grid
  /// triangulation. Points no triangle uses are not part of the mesh.
  std::vector<std::array<uint16_t, 3>> triangles;
  /// Lines inside the patch (x = seamX, y = seamY; -1: none) whose vertices move only along
  /// them, as a side's do; where a seam meets a side or the other seam the vertex is locked.
  int32_t seamX = -1, seamY = -1;
  /// No collapse has an error below this (metres): a root's collapses wait for its level.
  /// Each vertex's floor is spread over [errorFloor, kMorphSpan errorFloor), so that they do
  /// not all start geomorphing at once.
  float errorFloor = 0.0f;
  /// Collapses with an error up to this are applied at build time (makeProgressiveMesh's
  /// maxError): they never geomorph, so they hold no neighbour back.
  float bakedError = 0.0f;
  /// The order ends before the first collapse whose error would exceed this (metres): a node
  /// below the top of a VIPM tree stops where its parent takes over.
  float lastError = std::numeric_limits<float>::infinity();
  GeomorphSpacing spacing = GeomorphSpacing::kOn;
};

/// Greedy collapse order of `patch` until no collapse is allowed, from `start`. Pure and
/// deterministic. The errors start at the starting mesh's own error.
CollapseOrder buildCollapseOrder(const GridPatch& patch, MaterialRules rules,
                                 const CollapseStart& start = {});

}  // namespace terralod
