#pragma once
// Where the builder gets heights from: rectangular windows for the passes that sweep the data,
// and single points for the sparse accesses of coarse chunks. Coordinates are grid points;
// points outside the data take the nearest data sample (edge replication), so the padded part
// of the chunk tree has heights too. Voids must already be filled.

#include <cstdint>
#include <vector>

#include "terralod/core/result.h"
#include "terralod/raster/heightfield.h"

namespace terralod {

class HeightWindows {
 public:
  virtual ~HeightWindows() = default;
  /// Fills out[(y - y0) * w + (x - x0)] for the window; `worker` identifies the calling
  /// thread (0 .. threads-1) so implementations can keep per-thread state.
  virtual Status read(int32_t x0, int32_t y0, int32_t w, int32_t h, float* out,
                      unsigned worker) = 0;
};

/// Reads the (side + 1)² samples of the square at (x0, y0) into `closed` (rows of side + 1).
/// With `margin` > 0 one read serves a texture pass too: the square and `margin` more samples
/// on every side go into `margined` (rows of side + 1 + 2 margin), and the square is copied
/// out of it.
Status readWithMargin(HeightWindows& windows, int32_t x0, int32_t y0, int32_t side, int32_t margin,
                      std::vector<float>& margined, float* closed, unsigned worker);

class HeightSampler {
 public:
  virtual ~HeightSampler() = default;
  /// Height at one grid point. Thread-safe.
  virtual double at(int32_t x, int32_t y) const = 0;
};

/// Both views over an in-memory heightfield (the common case).
class MemoryHeights final : public HeightWindows, public HeightSampler {
 public:
  explicit MemoryHeights(const Heightfield& heights) : mHeights(heights) {}
  Status read(int32_t x0, int32_t y0, int32_t w, int32_t h, float* out, unsigned) override;
  double at(int32_t x, int32_t y) const override { return mHeights.at(x, y); }

 private:
  const Heightfield& mHeights;
};

}  // namespace terralod
