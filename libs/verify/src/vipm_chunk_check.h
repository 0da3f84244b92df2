#pragma once
// Checks one VIPM chunk blob (docs/format.md "VIPM chunk blobs") against the source, level by
// level, independently of the builder's and the runtime's bookkeeping: each level's mesh is
// made by renaming the finest triangles through the collapses one at a time (the naive way,
// not the reconstruction's edit lists) and rasterised over the chunk's source samples.

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "terralod/format/vipm_chunk_codec.h"
#include "terralod/raster/heightfield.h"
#include "terralod/vipm/collapse_order.h"

namespace terralod {

struct MaterialMap;

/// One side of a chunk, south, east, north, west: per grid point along it (west to east,
/// south to north), the lowest and highest height any level's border polyline has there.
struct SideEnvelope {
  std::vector<double> low, high;
};

struct VipmChunkCheck {
  uint64_t levels = 0;        ///< levels checked (collapses + 1)
  uint64_t samples = 0;       ///< source samples compared, over all levels
  uint64_t uncovered = 0;     ///< samples a level's triangles miss, over all levels
  double finestError = 0;     ///< true error of the finest level
  double worstMargin = 1e30;  ///< smallest (recorded error - true error) over the levels
  uint64_t collapsesChecked = 0;
  uint64_t ruleViolations = 0;      ///< collapses breaking a material rule
  uint64_t materialMismatches = 0;  ///< vertices whose material is not the source's
  uint64_t partLevelsChecked = 0;   ///< levels at which the parts were compared
  std::array<SideEnvelope, 4> sides;
  /// The coarsest level's height at every grid point of the chunk (y * width + x).
  std::vector<double> coarsestHeights;
  std::vector<std::string> problems;  ///< what is wrong, one line each (without the chunk name)
};

/// Heights differ from what the builder computed in single precision by this much relative to
/// the height (metres per metre of |height|), on top of kVerifySlack.
inline constexpr double kVipmFloatSlack = 1e-6;

/// Checks `chunk` whose south-west grid point is (x0, y0) in `source`. `materials`: the
/// source's material map, or null when it cannot be had (the rules are then checked against
/// the stored vertex materials only). Collapses breaking a material rule are counted always,
/// and are problems when the tileset promises the rules.
VipmChunkCheck checkVipmChunk(const VipmChunkData& chunk, int64_t x0, int64_t y0,
                              const Heightfield& source, const MaterialMap* materials,
                              MaterialRules promised);

}  // namespace terralod
