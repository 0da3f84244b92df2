#pragma once
// The bench's quality figures, measured against the source heightfield on the CPU from the
// chunks a frame selected (decoded from the tileset as the renderer draws them):
//  - screen-space error: over every source sample in view, |true height - drawn (morphed)
//    surface height| * K / distance from the eye;
//  - pops: from frame i's camera, the surface of frame i-1's selection and of frame i's, both
//    morphed for frame i, compared at every sample in view where the selections differ (on a
//    border between chunks of different levels, where each side has several heights, the
//    least difference between them);
//  - holes: background pixels of a look-down image over the data.

#include <cstdint>
#include <span>
#include <unordered_map>
#include <vector>

#include "terralod/format/tileset_reader.h"
#include "terralod/raster/heightfield.h"
#include "terralod/render/image.h"
#include "terralod/runtime/chunk_tree.h"
#include "terralod/runtime/selection.h"
#include "terralod/runtime/view.h"

namespace terralod {

/// How far (pixels) a rasteriser may move an edge by snapping vertices to its subpixel grid:
/// one subpixel of GL_SUBPIXEL_BITS = 8, as Mesa's llvmpipe and NVIDIA GPUs report (the GL
/// minimum is 4). The hole count leaves out pixel centres this close to the data's outer edge.
inline constexpr double kRasterPrecisionPx = 1.0 / 256.0;

class QualityMetrics {
 public:
  /// `source` is the tileset's source grid; every `stride`-th sample (in x and y) is measured.
  QualityMetrics(const TilesetReader& tileset, const ChunkTree& tree, const Heightfield& source,
                 int stride, unsigned threads);

  /// The largest screen-space error of the drawn surface of `selection` in `view`, pixels.
  Result<double> maxErrorPixels(const View& view, std::span<const SelectedChunk> selection);

  /// The largest screen-space change between `previous` and `current` selections, both
  /// evaluated with morph parameters for `view` (frame i's camera), pixels.
  Result<double> maxPopPixels(const View& view, const SelectionOptions& options,
                              std::span<const SelectedChunk> previous,
                              std::span<const SelectedChunk> current);

  /// Pixels of `image` (rendered from `view` without a sky) with exactly the `background`
  /// colour whose ray certainly meets the terrain (it stays over the data's footprint from the
  /// eye, or the data's top if lower, down to the data's lowest height), i.e. holes. A ray
  /// within kRasterPrecisionPx of the data's outer edge does not count: whether the
  /// rasteriser covers that pixel is decided by how it rounds the edge, not by the surface.
  /// The eye must be above the ground.
  uint64_t holes(const Image& image, const View& view, std::array<uint8_t, 3> background) const;

  int stride() const { return mStride; }

 private:
  struct CachedChunk {
    ChunkGeometry geometry;
    double truthMin = 0, truthMax = 0;  // source heights over the chunk's footprint
    Box truthBox;                       // the footprint's samples at their true heights, metres
    // The largest |true - drawn height| at the measured samples of each surface triangle (all
    // parts' in order) and of the whole chunk, at any morph parameter: the drawn height at a
    // sample is linear in t, so its error at any t is at most the larger of those at 0 and 1.
    std::vector<float> triangleError;
    double error = 0;
  };
  // Decodes a chunk (once) and finds the source's height range under it. Not thread-safe.
  Result<const CachedChunk*> chunk(uint32_t node);
  // Calls visit(x, y, drawnHeight) for each measured sample under the chunk's surface at morph
  // t, skipping triangles whose samples cannot be in `view` (drawn and true heights both
  // considered) and those for which keep(triangle, box) is false (triangle counts surface
  // triangles over all parts; box bounds its samples at drawn and true heights). The chunk must
  // have been cached. Thread-safe.
  // A null view keeps every triangle.
  template <typename Visit, typename Keep>
  void rasterizeChunk(uint32_t node, const CachedChunk& cached, double morph, const View* view,
                      Visit&& visit, Keep&& keep) const;
  template <typename Visit>
  void rasterizeChunk(uint32_t node, double morph, const View& view, Visit&& visit) const {
    rasterizeChunk(node, mChunks.at(node), morph, &view, visit,
                   [](size_t, const Box&) { return true; });
  }
  // Fills a decoded chunk's triangleError and error.
  void measureChunkError(uint32_t node, CachedChunk& c) const;
  bool inView(const View& view, int64_t x, int64_t y, double z) const;

  const TilesetReader& mTileset;
  const ChunkTree& mTree;
  const Heightfield& mSource;
  int mStride;
  unsigned mThreads;
  std::unordered_map<uint32_t, CachedChunk> mChunks;
  std::vector<uint8_t> mMark;  // per node, which selection it is in (pops)
};

/// The camera that looks for holes from `eye`: 60 degrees down, facing `view`'s heading.
Camera lookDownCamera(const View& view);

}  // namespace terralod
