#pragma once
// Vegetation over a tileset, one software picture a frame (papers/tiling-layered-depth-images.md
// §5): the tiles a view draws (vegetation_field.h) over the tileset's heights
// (tileset_corner_heights.h), their LDIs (ldi_cache.h) warped on the CPU (frame_warp.h). The
// picture goes to a render layer that z-composites it over the terrain (picture_layer.h).
// Render thread only.

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <unordered_map>
#include <utility>

#include "terralod/core/result.h"
#include "terralod/format/tileset_reader.h"
#include "terralod/runtime/chunk_tree.h"
#include "terralod/vegetation/frame_warp.h"
#include "terralod/vegetation/ldi_cache.h"
#include "terralod/vegetation/tileset_corner_heights.h"
#include "terralod/vegetation/vegetation_field.h"

namespace terralod::veg {

struct VegetationOptions {
  FieldOptions field;
  FrameWarpOptions warp;
  std::optional<uint64_t> seed;                     ///< the tiling's; default the file's
  uint64_t ldiBudgetBytes = uint64_t{128} << 20;    ///< decoded LDIs
  uint64_t heightBudgetBytes = uint64_t{16} << 20;  ///< corner heights
  std::function<void(const std::string&)> log;      ///< one line per unreadable LDI or chunk
};

struct VegetationFrameStats {
  FieldStats field;
  FrameWarpStats warp;
  double selectMs = 0;         ///< choosing the tiles (heights read included)
  double readMs = 0;           ///< reading and decoding LDIs this frame (part of warp.warpMs)
  uint64_t residentBytes = 0;  ///< decoded LDIs and corner heights
};

/// What paint() does with the tiles' choices of LDIs (for measuring pops: the picture with
/// the last frame's choices against this frame's, both from this frame's camera).
enum class PaintMode {
  kFrame,            ///< a new frame: its choices become the current ones, the old the last
  kRepaint,          ///< the current choices again (nothing remembered)
  kPreviousChoices,  ///< each tile the last frame drew as it chose then (opacities as now)
};

class VegetationPainter {
 public:
  /// Opens the .tlv (a path or an http(s):// URL) for vegetation over `tileset` (both must
  /// outlive the painter).
  static Result<std::unique_ptr<VegetationPainter>> open(const std::string& pathOrUrl,
                                                         const TilesetReader& tileset,
                                                         const ChunkTree& tree,
                                                         VegetationOptions options);

  /// Paints the vegetation `view` sees into `picture` (the rows lastFrame().warp reports),
  /// in the mode setMode() chose.
  void paint(const View& view, const PictureSpans& picture);
  void setMode(PaintMode mode) { mMode = mode; }
  /// Whether the last kFrame paint chose other LDIs (a resolution or direction, or a blend's
  /// members) for some tile than the one before did.
  bool choicesChanged() const { return mChoicesChanged; }

  const VegetationFrameStats& lastFrame() const { return mLast; }
  const FieldLayout& layout() const { return mLayout; }
  const VegetationReader& file() const { return *mFile; }

 private:
  VegetationPainter(std::unique_ptr<VegetationReader> file, const TilesetReader& tileset,
                    const ChunkTree& tree, VegetationOptions options);
  std::unique_ptr<VegetationReader> mFile;
  VegetationOptions mOptions;
  FieldLayout mLayout;
  LdiCache mLdis;
  TilesetCornerHeights mHeights;
  FrameWarper mWarper;
  VegetationFrameStats mLast;
  PaintMode mMode = PaintMode::kFrame;
  // Each tile's LDIs, by tile (y << 32 | x): this frame's and the last's.
  using Choices = std::unordered_map<uint64_t, std::pair<std::array<TileLdi, 4>, int>>;
  Choices mCurrent, mPrevious;
  bool mChoicesChanged = false;
};

}  // namespace terralod::veg
