#pragma once
// The mutable triangle mesh a collapse order is built on: triangles over a GridPatch's points,
// per-point incident triangles, and the tests and error of a candidate half-edge collapse.
// Internal to libs/vipm (collapse_order.cpp and tests).

#include <array>
#include <cstdint>
#include <limits>
#include <unordered_map>
#include <vector>

#include "terralod/vipm/collapse_order.h"
#include "terralod/vipm/grid_patch.h"

namespace terralod {

/// Largest |sample - plane| over the grid samples inside the closed triangle (a, b, c) of a
/// patch (counter-clockwise, positive area); for a sparse patch a bound on it over the sample
/// blocks (exact when they are single samples). Stops early, returning a value > `limit`, once
/// a sample exceeds `limit`.
double triangleError(const GridPatch& patch, uint16_t a, uint16_t b, uint16_t c,
                     double limit = std::numeric_limits<double>::infinity());

class PatchMesh {
 public:
  /// The full grid triangulation of `patch`.
  PatchMesh(const GridPatch& patch, MaterialRules rules)
      : PatchMesh(patch, rules, gridTriangulation(patch.width, patch.height)) {}
  /// The mesh of `triangles` over `patch`'s points; vertices on x = seamX or y = seamY (-1:
  /// none) move only along those lines, as vertices on a side do.
  PatchMesh(const GridPatch& patch, MaterialRules rules,
            std::vector<std::array<uint16_t, 3>> triangles, int32_t seamX = -1, int32_t seamY = -1);

  /// The error of collapsing v onto u (the largest distance of the samples under the new
  /// triangles), or infinity when the collapse is not allowed or its error exceeds `limit`.
  double collapseError(uint16_t v, uint16_t u, double limit) const;
  /// Applies an allowed collapse.
  void collapse(uint16_t v, uint16_t u);

  /// Points sharing an edge with `v` (unordered, no repeats), appended to `out`.
  void neighbours(uint16_t v, std::vector<uint16_t>& out) const;
  bool alive(uint16_t v) const { return !mIncident[v].empty(); }
  /// Alive triangles, in their original order (re-pointed corners).
  std::vector<std::array<uint16_t, 3>> aliveTriangles() const;

 private:
  int sides(uint16_t v) const;
  bool onMaterialBoundary(uint16_t v) const;
  bool materialStays(uint16_t v, uint16_t u) const;
  // triangleError through a cache: the same new triangles come up again and again as a
  // vertex's candidates are re-evaluated after collapses nearby.
  double cachedTriangleError(uint16_t a, uint16_t b, uint16_t c, double limit) const;

  const GridPatch& mPatch;
  MaterialRules mRules;
  int32_t mSeamX, mSeamY;
  std::vector<std::array<uint16_t, 3>> mTriangles;
  std::vector<std::vector<uint32_t>> mIncident;  // per point, its alive triangles
  struct KnownError {
    double error;
    bool exact;  // otherwise a lower bound (a scan stopped early)
  };
  mutable std::unordered_map<uint64_t, KnownError> mErrors;
  // Per-point marks for neighbour sets without searching (a mark equal to the stamp is set).
  mutable std::vector<uint32_t> mMark, mMark2;
  mutable uint32_t mStamp = 0;
};

}  // namespace terralod
