#pragma once
// Height windows streamed from a DEM on disk, one GDAL reader per worker thread, so the whole
// raster is never in memory. While windows pass through it records what later passes need
// without the full raster: the samples on the block grid lines and on the data's north and
// east edges (see SparseHeights), the height range, and whether any void was met.

#include <atomic>
#include <memory>
#include <mutex>
#include <vector>

#include "terralod/build/height_source.h"
#include "terralod/build/sparse_heights.h"
#include "terralod/raster/dem_reader.h"
#include "terralod/raster/heightfield.h"

namespace terralod {

class DemWindows final : public HeightWindows {
 public:
  /// `reader` serves worker 0; other workers get their own reopened readers on first use.
  DemWindows(const DemReader& reader, unsigned workers, SparseHeights* record);

  Status read(int32_t x0, int32_t y0, int32_t w, int32_t h, float* out, unsigned worker) override;

  bool sawVoid() const { return mSawVoid.load(); }
  double minHeight() const;
  double maxHeight() const;
  /// Stops recording into the SparseHeights (later passes read the same windows again).
  void stopRecording() { mRecord = nullptr; }

  /// From now on copies the windows' samples into `field` (grid order, the raster's size), so
  /// that a raster within the memory budget is decoded once for both passes. A window
  /// (x0, y0, w, h) gives columns x0 .. x0 + w - 2 and rows y0 .. y0 + h - 2, and its last
  /// column and row where they reach the raster's last: pass 1's block windows (side + 1
  /// samples at multiples of the side) so give every sample once. Starts the count afresh.
  void keepInto(Heightfield& field);
  /// Whether exactly the raster's samples have been kept since keepInto.
  bool keptAll() const;

 private:
  const DemReader& mReader;
  std::vector<std::unique_ptr<DemReader>> mOwnReaders;
  std::mutex mOpenMutex;
  SparseHeights* mRecord;
  std::atomic<bool> mSawVoid{false};
  std::vector<double> mMin, mMax;  // per worker
  Heightfield* mKeep = nullptr;
  std::vector<uint64_t> mKept;  // samples kept, per worker
};

}  // namespace terralod
