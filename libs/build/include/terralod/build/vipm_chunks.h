#pragma once
// The chunks of a VIPM tileset (docs/format.md "VIPM tilesets"): a leaf's progressive mesh
// built from the DEM, and a root's fallback mesh joined from its children's coarsest levels.
// Pure functions of their inputs (deterministic), used by buildVipmTileset.

#include <cstdint>
#include <functional>
#include <limits>
#include <optional>
#include <vector>

#include "terralod/format/texture_codec.h"
#include "terralod/format/tileset_format.h"
#include "terralod/format/vipm_chunk_codec.h"
#include "terralod/materials/material.h"
#include "terralod/raster/heightfield.h"
#include "terralod/vipm/collapse_order.h"
#include "terralod/vipm/progressive_mesh.h"

namespace terralod {

/// A power of two no coarser than maxError / 8, doubled until a height range of `range` metres
/// fits 65000 steps (the builder passes the largest range of any root, so every chunk of the
/// tileset shares it and a root's heights are its children's exactly).
double vipmTilesetZStep(double maxError, double range);

/// A chunk's coarsest level in tileset terms: vertices at DEM grid points with their stored
/// heights (zBase + q zStep, zBase a multiple of the tileset's zStep).
struct CoarseMesh {
  std::vector<uint32_t> gridX, gridY;  ///< per vertex: DEM grid point
  std::vector<double> heights;         ///< per vertex: stored height (metres)
  std::vector<uint8_t> materials;      ///< per vertex
  std::vector<uint32_t> indices;       ///< triangles, counter-clockwise from above
  float error = 0.0f;                  ///< the level's error as stored (metres)
};

/// What building one leaf gives.
struct VipmLeaf {
  std::vector<uint8_t> blob;  ///< the encoded VIPM chunk
  NodeRecord node;            ///< minZ, maxZ, vertexCount, triangleCount, meshKind; no offsets
  CoarseMesh coarsest;
  /// Largest vertical distance, over every level, between a border grid point's source height
  /// and that level's border polyline (docs/format.md "Node fields").
  double borderDeviation = 0.0;
  uint32_t collapses = 0;
  double seconds = 0.0;  ///< CPU time building this leaf (its thread's)
};

struct VipmLeafParams {
  double zStep = 1.0;
  double maxError = 1.0;
  /// The coarsest level's error at most: collapses above it are left to the root.
  double coarsestError = std::numeric_limits<double>::infinity();
  MaterialRules rules = MaterialRules::kOn;
  int compressionLevel = 19;
};

/// Builds the leaf whose south-west grid point is (x0, y0), `width` x `height` points, from the
/// (void-filled) heights and the materials of every DEM grid point.
VipmLeaf buildVipmLeaf(const Heightfield& heights, const MaterialMap& materials, int32_t x0,
                       int32_t y0, int32_t width, int32_t height, const VipmLeafParams& params);

/// The border deviation of `mesh` over all its levels (see VipmLeaf): `source(x, y)` the source
/// height at the patch's grid point (x, y), `stored` every mesh vertex's stored height.
double borderDeviation(const ProgressiveMesh& mesh,
                       const std::function<double(int32_t, int32_t)>& source,
                       const std::vector<double>& stored);

/// The children's coarsest meshes joined on the root's grid (points deduplicated, first use
/// first), collapseCount 0, finestError the largest child error: a root's finest level.
/// (x0, y0) is the root's south-west grid point, width x height its points (<= 129).
VipmChunkData joinCoarsest(const std::vector<const CoarseMesh*>& children, int32_t x0, int32_t y0,
                           int32_t width, int32_t height, double zStep);

/// What building one root gives: a "blot" chunk (the paper's far chunks), its children's
/// coarsest levels joined and then simplified further without the material rules.
struct VipmRoot {
  std::vector<uint8_t> blob;
  NodeRecord node;      ///< as VipmLeaf's
  CoarseMesh coarsest;  ///< what the node above joins
  /// As VipmLeaf's, over the root's outer sides.
  double borderDeviation = 0.0;
  /// A bound on the vertical distance between the source samples on the children's shared
  /// sides (x or y = 64) and either side's polyline there, at every level: its coarsest
  /// level's error (errors are measured over closed triangles, seams included); 0 for a root
  /// no wider and no taller than a leaf (no shared sides).
  double seamDeviation = 0.0;
  uint32_t collapses = 0;
  double seconds = 0.0;
};

/// Builds the root whose south-west grid point is (x0, y0), `width` x `height` points (<=
/// 129), from its children's coarsest levels. Its finest level is those levels joined
/// (joinCoarsest); its collapses move vertices on the children's shared sides only along
/// them (the centre and the sides' ends stay), and their errors are at least `levelError`
/// (the roots' level error), so a root draws its children's coarsest levels until its own
/// allowance passes the level error, and its first collapses geomorph in from there.
/// Under upper levels its collapses stop at `lastError`, where its parent takes over.
VipmRoot buildVipmRoot(const Heightfield& heights, const MaterialMap& materials,
                       const std::vector<const CoarseMesh*>& children, int32_t x0, int32_t y0,
                       int32_t width, int32_t height, double zStep, double levelError,
                       double lastError, int compressionLevel);

/// Cells a side of the sample blocks an upper node's errors are bounded over: its cells / 128
/// (so about 128 x 128 blocks a node, whatever its level).
int32_t vipmUpperSampleStep(int32_t cells);

/// Builds a node above the roots (256, 512, ... cells: `cells`), whose south-west grid point is
/// (x0, y0), `width` x `height` points, from its children's coarsest levels: its finest level
/// is them joined with their cracks closed (the T-junctions where they, and their own
/// children inside them, meet: each open edge on a line inside is split at the other side's
/// points there, as fan stitching draws them side by side), so it has no seams, and its
/// collapses (without the material rules) move every vertex but its sides', wait for
/// `levelError` and stop at `lastError`. Its grid is too large for a sample per point, so its
/// errors are bounds over blocks of vipmUpperSampleStep(cells) points (SampleBlocks), and its
/// vertices are stored as 32-bit grid points (blob version 2 once a side is over 129 points).
/// Nothing when the join has more than kVipmMaxNodeVertices vertices (a u16 index each): on
/// terrain too rough for the level's error its children hardly simplify.
inline constexpr size_t kVipmMaxNodeVertices = 65536;
std::optional<VipmRoot> buildVipmUpperNode(const Heightfield& heights,
                                           const std::vector<const CoarseMesh*>& children,
                                           int32_t x0, int32_t y0, int32_t cells, int32_t width,
                                           int32_t height, double zStep, double levelError,
                                           double lastError, int compressionLevel);

/// A leaf or root as buildVipmLeaf or buildVipmRoot made it, from its stored blob (an edit
/// rebuilds only the chunks its strokes reach): the blob as it is, its node fields, and what
/// the roots and flange depths need (coarsest level, border and seam deviations), worked out
/// again from the blob and the heights, which must be those it was built from. Fails when the
/// blob does not decode.
Result<VipmLeaf> reuseVipmLeaf(std::vector<uint8_t> blob, const Heightfield& heights,
                               const MaterialMap& materials, int32_t x0, int32_t y0, int32_t width,
                               int32_t height, double zStep);
Result<VipmRoot> reuseVipmRoot(std::vector<uint8_t> blob, const Heightfield& heights,
                               const MaterialMap& materials, int32_t x0, int32_t y0, int32_t width,
                               int32_t height, double zStep);
/// As reuseVipmRoot, for a node above the roots.
Result<VipmRoot> reuseVipmUpperNode(std::vector<uint8_t> blob, const Heightfield& heights,
                                    int32_t x0, int32_t y0, int32_t width, int32_t height,
                                    double zStep);

/// A chunk's whole grid as a VIPM chunk without collapses: every grid point a vertex (heights
/// on the tileset's step `zStep`), the grid's triangles, so it is exact up to that rounding.
/// What an editor draws while a chunk's progressive mesh is made again (a few milliseconds,
/// where the collapse order takes seconds): the blob and its node fields (as VipmLeaf's).
struct VipmGridChunk {
  std::vector<uint8_t> blob;
  NodeRecord node;
};
VipmGridChunk buildVipmGridChunk(const Heightfield& heights, const MaterialMap& materials,
                                 int32_t x0, int32_t y0, int32_t width, int32_t height,
                                 double zStep, int compressionLevel);

/// A VIPM node's texture (docs/format.md "VIPM tilesets"): one BC5 normal layer of n + 1
/// texels over grid square [x0, x0 + cells]^2, n = min(cells, 128) at a stride of cells / n
/// points, texel (i, j) the central-difference normal of the source heights sampled at that
/// stride at grid point (x0 + i stride, y0 + j stride) (points outside the data take the
/// nearest sample), mips by the default resampling (texture_encoder.h). A root (128 cells)
/// and its leaves (64) store the same texels where they overlap: their light does not depend
/// on their meshes. The encoded texture blob.
std::vector<uint8_t> buildVipmNormalMap(const Heightfield& heights, int32_t x0, int32_t y0,
                                        int32_t cells, double spacingX, double spacingY);

/// f32 bounds that contain [lo, hi] (rounded outward).
float floatBelow(double v);
float floatAbove(double v);

}  // namespace terralod
