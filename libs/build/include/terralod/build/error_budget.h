#pragma once
// How the requested leaf error becomes per-level thresholds for the mesher.
//
// Level L promises a geometric error of at most levelError[L] = leafError * 2^(depth-L) for the
// surface as stored, i.e. after heights are quantised to zStep[L]. Quantisation moves a vertex
// by at most zStep/2 and so the surface by at most zStep/2, so the mesher refines against
// buildThreshold[L] = levelError[L] - zStep[L]/2. zStep[L] is fixed per level: the coarsest step
// for which every chunk's height range (terrain relief plus the deepest possible skirt) fits
// 16 bits, and never finer than levelError[L]/64 (finer steps only cost bytes).

#include <cstdint>
#include <limits>
#include <vector>

#include "terralod/build/tree_layout.h"
#include "terralod/core/result.h"

namespace terralod {

struct ErrorBudget {
  std::vector<double> levelError;       ///< root first
  std::vector<double> zStep;            ///< height quantisation step per level
  std::vector<double> buildThreshold;   ///< levelError - zStep/2
  std::vector<double> chunkRangeBound;  ///< largest height range of any chunk incl. skirts

  /// Activation of a vertex whose diamond has conservative error `error`: the number of
  /// levels, counted from the leaves, whose threshold it exceeds (0 .. depth+1).
  uint8_t activation(double error) const {
    const int32_t levels = static_cast<int32_t>(buildThreshold.size());
    uint8_t a = 0;
    while (a < levels && error > buildThreshold[levels - 1 - a]) ++a;
    return a;
  }
  /// The same, knowing it is at least `from` (skips the thresholds below).
  uint8_t activationFrom(double error, uint8_t from) const {
    const int32_t levels = static_cast<int32_t>(buildThreshold.size());
    uint8_t a = from;
    while (a < levels && error > buildThreshold[levels - 1 - a]) ++a;
    return a;
  }
  /// The error a vertex must exceed to have an activation above `activation`.
  double thresholdAbove(uint8_t activation) const {
    const int32_t levels = static_cast<int32_t>(buildThreshold.size());
    return activation < levels ? buildThreshold[levels - 1 - activation]
                               : std::numeric_limits<double>::infinity();
  }
  /// Activation a vertex needs to be part of level L's meshes.
  uint8_t activationForLevel(int32_t level) const {
    return static_cast<uint8_t>(static_cast<int32_t>(buildThreshold.size()) - level);
  }
};

/// `heightRange` is max - min of the (void-filled) heights. Fails when the leaf error is too
/// small to be kept with 16-bit heights over that relief.
Result<ErrorBudget> makeErrorBudget(const TreeLayout& layout, double leafError, double heightRange);

}  // namespace terralod
