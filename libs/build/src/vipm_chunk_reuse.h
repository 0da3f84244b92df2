#pragma once
// The chunks of an earlier VIPM build that an edit does not reach (BuildOptions::reuse): kept
// as they are instead of being built again.

#include <memory>
#include <optional>
#include <vector>

#include "terralod/build/builder.h"
#include "terralod/build/tree_layout.h"
#include "terralod/format/tileset_reader.h"
#include "terralod/materials/terrain_edits.h"

namespace terralod {

class VipmChunkReuse {
 public:
  /// nullopt when options.reuse is empty, or names a tileset that is not an earlier build of
  /// this source with these options (same size, spacing, levels, recorded options, zStep, and
  /// edits a prefix of options.edits): then every chunk is built.
  static std::optional<VipmChunkReuse> open(const BuildOptions& options, const DemInfo& info,
                                            const TreeLayout& layout, double zStep);

  /// The earlier build's bytes of node `index`, whose grid points are [x0, x0 + width) x
  /// [y0, y0 + height), when none of them nor their neighbours (its normal map's central
  /// differences) is touched by a stroke the earlier build did not have; nullopt otherwise or
  /// when they cannot be read.
  std::optional<NodeBytes> clean(uint32_t index, int32_t x0, int32_t y0, int32_t width,
                                 int32_t height) const;

  /// The earlier build's error of `level` (a level's nodes are kept only when it has not
  /// changed).
  double levelError(int32_t level) const { return mOld->header().levelError[size_t(level)]; }

 private:
  std::shared_ptr<const TilesetReader> mOld;
  std::vector<GridWindow> mStrokes;  ///< what each new stroke touches
};

}  // namespace terralod
