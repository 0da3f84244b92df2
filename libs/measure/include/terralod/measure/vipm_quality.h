#pragma once
// The bench's quality figures on VIPM tilesets (docs/format.md "VIPM tilesets"), measured on
// what the VIPM kind draws: each selected chunk's surface at the θ the kind drew it with
// (vipmDrawnTheta), i.e. the collapses morphWindow applies and the vertices morphPositions
// geomorphs (libs/vipm), against the source samples as QualityMetrics measures static chunks:
//  - error: over every measured source sample in view, |true - drawn height| * K / distance;
//  - pops, as on static tilesets the change caused by the LOD state alone: from frame i's
//    camera, frame i-1's state (each chunk's applied and geomorphing collapses, chosen by the
//    θ it was drawn with then) geomorphed for frame i's θ, against frame i's. Geomorphing is
//    continuous in θ, so what is left is a collapse entering or leaving the geomorph between
//    the two frames, or a root handing over to its leaves; without geomorphing (--no-morph)
//    whole collapses show;
//  - the morph step: the same comparison with frame i-1's state at its own θ, i.e. everything
//    that moved between the two frames' pictures, the geomorph's steady motion included (it
//    grows with the camera's speed).
//  Chunks drawn alike in both (same node, same collapses, no geomorph or the same θ) are left
//  out.
// With fan stitching (VipmStitch::kFans) the error is measured on the fans too, made from the
// frame's chunks as the kind makes them, and pops compare each frame's chunks with their fans
// (a merge into a node above the roots, whose children's cracks are closed as fans close them,
// changes no height there).

#include <array>
#include <cstdint>
#include <span>
#include <unordered_map>
#include <vector>

#include "terralod/format/tileset_reader.h"
#include "terralod/raster/heightfield.h"
#include "terralod/render/vipm_chunk_kind.h"
#include "terralod/runtime/chunk_tree.h"
#include "terralod/runtime/selection.h"
#include "terralod/runtime/view.h"
#include "terralod/vipm/progressive_mesh.h"
#include "terralod/vipm/vipm_fans.h"
#include "terralod/vipm/vipm_levels.h"

namespace terralod {

class VipmQuality {
 public:
  /// A chunk as drawn in one frame.
  using Drawn = VipmChunkAt;  ///< node, θ that chose its collapses, θ of its geomorph
  /// `source` is the tileset's source grid; every `stride`-th sample (x and y) is measured.
  /// `geomorph`: whether the kind geomorphs (SelectionOptions::morph).
  VipmQuality(const TilesetReader& tileset, const ChunkTree& tree, const Heightfield& source,
              int stride, unsigned threads, Geomorph geomorph,
              VipmStitch stitch = VipmStitch::kFlanges);

  /// The chunks of `selection` with the θ the VIPM kind draws them with in `view`.
  static std::vector<Drawn> drawn(const ChunkTree& tree, const View& view, double tau,
                                  std::span<const SelectedChunk> selection);

  /// Frame i-1's chunks `previous` (selected as `previousSelection`) in the state they were
  /// drawn in, geomorphed for `view`: morphTheta from their morph parameter re-evaluated for
  /// `view`, as static chunks are for pops.
  static std::vector<Drawn> geomorphedFor(const ChunkTree& tree, const View& view,
                                          const SelectionOptions& options,
                                          std::span<const SelectedChunk> previousSelection,
                                          std::span<const Drawn> previous);

  /// The largest screen-space error of the drawn surface of `chunks` in `view`, pixels.
  Result<double> maxErrorPixels(const View& view, std::span<const Drawn> chunks);
  /// The largest screen-space movement, seen from `view`, between the surfaces `previous` and
  /// `current` draw (for pops, `previous` is frame i-1's chunks with morphTheta for `view`).
  Result<double> maxPopPixels(const View& view, std::span<const Drawn> previous,
                              std::span<const Drawn> current);

 private:
  struct Chunk {
    ProgressiveMesh mesh;
    VipmLevels levels;
    StitchChunk where;  // where it lies, for rounding its geomorphing points as drawn
    VipmStitcher stitcher;
    std::vector<uint8_t> materials;
    std::vector<std::array<float, 3>> own;  // grid x, grid y, metres above zBase
    double zBase = 0.0;
    int64_t x0 = 0, y0 = 0, maxX = 0, maxY = 0;  // source samples it covers
    double truthMin = 0.0, truthMax = 0.0;       // source heights under it
  };
  // A drawn triangle: absolute sample coordinates (fractional while geomorphing), metres.
  struct Triangle {
    std::array<std::array<double, 3>, 3> v;
  };
  // Decodes a chunk once. Not thread-safe.
  Result<Chunk*> chunk(uint32_t node);
  // A chunk's drawn triangles in one frame.
  struct Surface {
    const Chunk* chunk;
    std::vector<Triangle> triangles;
  };
  // Each of `chunks` (one frame's) as the kind draws them, with their fans if stitched by
  // fans. Not thread-safe.
  Result<std::vector<Surface>> surfaces(std::span<const Drawn> chunks);
  // Sets the chunk's collapses for `d` and returns its vertices where the kind draws them.
  std::vector<std::array<float, 3>> drawnPositions(Chunk& c, const Drawn& d);
  // Its living triangles at `drawn`, those `fans` replace (if any) left out and the fans added.
  std::vector<Triangle> triangles(const Chunk& c, std::span<const std::array<float, 3>> drawn,
                                  const StitchFans* fans) const;
  // Calls visit(x, y, drawnHeight) at every measured sample under the triangles that may be in
  // view (drawn and true heights considered).
  template <typename Visit>
  void rasterize(const Chunk& c, std::span<const Triangle> triangles, const View& view,
                 Visit&& visit) const;
  bool inView(const View& view, int64_t x, int64_t y, double z) const;

  const TilesetReader& mTileset;
  const ChunkTree& mTree;
  const Heightfield& mSource;
  int mStride;
  unsigned mThreads;
  Geomorph mGeomorph;
  VipmStitch mStitch;
  std::unordered_map<uint32_t, Chunk> mChunks;
  std::vector<std::vector<double>> mSpareGrids;  // maxPopPixels' sample grids, for the next call
};

}  // namespace terralod
