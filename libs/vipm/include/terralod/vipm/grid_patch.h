#pragma once
// The samples of one VIPM chunk: a rectangle of DEM grid points with their heights and
// material classes. A full chunk is 65 x 65 points (64 x 64 cells, so chunks line up with the
// chunk quadtree's 64-cell leaves); chunks on the data's east and north edges can be narrower.
// Neighbouring chunks share their border points.

#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

namespace terralod {

/// Cells along each side of a full VIPM chunk.
inline constexpr int32_t kVipmChunkCells = 64;

/// The source samples of a sparse patch, as bounds over blocks of `step` x `step` grid points:
/// block (i, j) holds the samples with x in [i step, (i + 1) step) and y in [j step,
/// (j + 1) step), clipped to the patch. Each block has a plane, height a + bx (x - cx) +
/// by (y - cy) with (cx, cy) the centre of its samples' rectangle, and the range [lo, hi] of
/// its samples' heights above that plane (a slope inside a block costs nothing; a bound on
/// plain heights would count it twice). With step 1 each block is one sample, exactly.
struct SampleBlocks {
  int32_t step = 1;
  int32_t columns = 0, rows = 0;  ///< blocks along x and y
  /// Per block (row-major, south row first).
  std::vector<float> a, bx, by, lo, hi;
};

/// The blocks of `step` points over a patch of width x height points whose source height at
/// point (x, y) is `sample(x, y)`: each block's plane by its mean and its mean slopes across
/// (any plane bounds; a close one bounds tightly).
SampleBlocks makeSampleBlocks(int32_t width, int32_t height, int32_t step,
                              const std::function<float(int32_t, int32_t)>& sample);

/// A patch is dense (a chunk: every grid point a possible vertex, ids y * width + x) or sparse
/// (a node above the roots, whose grid is too large for that: ids index its own points, given
/// by their grid coordinates, and errors are bounded over SampleBlocks instead of scanned over
/// every sample).
struct GridPatch {
  int32_t width = 0;   ///< points along x (east), 2 .. kVipmChunkCells + 1 when dense
  int32_t height = 0;  ///< points along y (north)
  /// Dense: row-major, south row first: point (x, y) is at y * width + x. Sparse: per point.
  /// Metres: the source samples every error is measured against.
  std::vector<float> heights;
  /// Same layout: the heights the mesh's vertices get (e.g. the stored, quantised ones). Empty:
  /// the samples themselves.
  std::vector<float> vertexHeights;
  /// Same layout: the point's material index (into the tileset's material table).
  std::vector<uint8_t> materials;
  /// Sparse: per point, its grid coordinates (0 .. width - 1, 0 .. height - 1); empty: dense.
  std::vector<int32_t> pointX, pointY;
  /// Sparse: the samples the errors are bounded over.
  SampleBlocks samples;

  bool sparse() const { return !pointX.empty(); }
  /// Dense only.
  uint16_t id(int32_t x, int32_t y) const { return uint16_t(y * width + x); }
  int32_t xOf(uint32_t id) const { return sparse() ? pointX[id] : int32_t(id) % width; }
  int32_t yOf(uint32_t id) const { return sparse() ? pointY[id] : int32_t(id) / width; }
  /// The point's grid point, y * width + x.
  uint32_t gridPoint(uint32_t id) const {
    return sparse() ? uint32_t(pointY[id]) * uint32_t(width) + uint32_t(pointX[id]) : id;
  }
  /// Dense only.
  float heightAt(int32_t x, int32_t y) const { return heights[size_t(y) * width + x]; }
  float vertexHeight(uint32_t id) const {
    return vertexHeights.empty() ? heights[id] : vertexHeights[id];
  }
  uint32_t pointCount() const {
    return sparse() ? uint32_t(pointX.size()) : uint32_t(width) * uint32_t(height);
  }
};

}  // namespace terralod
