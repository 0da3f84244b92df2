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
  /// The finest and the coarsest level's height at every grid point (y * width + x).
  std::vector<double> finestHeights, coarsestHeights;
  /// Roots (wider than a leaf): the finest level of each 64-cell quarter, SW, SE, NW, NE (65 x
  /// 65 grid points each, NaN where none of its triangles reach), drawn from the triangles
  /// inside that quarter only: its children's meshes joined side by side, whose shared sides
  /// need not match (flanges close them, as between leaves).
  std::array<std::vector<double>, 4> quarters;
  /// Roots: the largest vertical gap, at any level and grid point, between the two sides'
  /// polylines on the children's shared lines (x or y = 64), which its flanges must close.
  double seamGap = 0;
  /// Nodes above the roots (checkVipmUpperNode): the finest and the coarsest level's vertices
  /// (grid x, grid y, stored height), sorted.
  std::vector<std::array<double, 3>> finestPoints, coarsestPoints;
  std::vector<std::string> problems;  ///< what is wrong, one line each (without the chunk name)
};

/// Heights differ from what the builder computed in single precision by this much relative to
/// the height (metres per metre of |height|), on top of kVerifySlack.
inline constexpr double kVipmFloatSlack = 1e-6;

/// Checks `chunk` whose south-west grid point is (x0, y0) in `source`. `materials`: the
/// source's material map, or null when it cannot be had (the rules are then checked against
/// the stored vertex materials only). Collapses breaking a material rule are counted always,
/// and are problems when `promised` is kOn (a leaf of a tileset built with the rules; roots
/// are simplified without them).
VipmChunkCheck checkVipmChunk(const VipmChunkData& chunk, int64_t x0, int64_t y0,
                              const Heightfield& source, const MaterialMap* materials,
                              MaterialRules promised);

/// Checks a node above the roots (any size, version 2 blobs): at up to kVipmUpperLevelsVerified
/// levels, its triangles (made by renaming, as checkVipmChunk does) rasterised over every
/// source sample (true error against the recorded one, coverage), and at every level its
/// sides' polylines (the envelopes, for the flanges). Fills levels, samples, uncovered,
/// finestError, worstMargin, sides, finestPoints, coarsestPoints and problems; no dense
/// heights, no material rules (nodes above the roots are simplified without them).
VipmChunkCheck checkVipmUpperNode(const VipmChunkData& chunk, int64_t x0, int64_t y0,
                                  const Heightfield& source);

struct NormalMapCheck {
  uint64_t texels = 0;  ///< mip 0 texels compared
  double worst = 0;     ///< largest |stored - true| of a normal's x or y component
  std::string problem;  ///< the first texel out of tolerance, or ""
};

/// Checks a VIPM node's stored normal map (decodeVipmNormalMap's layer) whose texel (i, j) is
/// grid point (x0 + i stride, y0 + j stride): every mip 0 texel, BC5-decoded, against the unit
/// normal of the source by central differences there over the grid at that stride (the
/// nearest sample outside the data). The tolerance is what
/// BC5 can lose: per 4 x 4 block and channel, one step of its 8-value palette ((max - min of
/// the block's true values) / 7) plus 2/255 for 8-bit rounding, in (n + 1) / 2 units.
NormalMapCheck checkVipmNormalMap(const TextureLayer& layer, int64_t x0, int64_t y0,
                                  const Heightfield& source, double spacingX, double spacingY,
                                  int64_t stride = 1);

}  // namespace terralod
