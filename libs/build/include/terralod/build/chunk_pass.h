#pragma once
// The second pass of the build: meshing, encoding and writing every chunk.
//
// Work is split by blocks (the chunk squares of the level whose side is blockCells): each
// block's window of heights is read once and every chunk below that level inside it is built
// from it. Chunks at the block level and above (few, large, sparse) come last, from heights
// that are either the whole raster (when it is in memory) or the SparseHeights recorded by the
// blocks. Blobs are written in a fixed order, so the file does not depend on thread timing.

#include <vector>

#include "terralod/build/activation_grid.h"
#include "terralod/build/error_budget.h"
#include "terralod/build/height_source.h"
#include "terralod/build/sparse_heights.h"
#include "terralod/build/texture_pass.h"
#include "terralod/build/tree_layout.h"
#include "terralod/core/progress.h"
#include "terralod/format/chunk_codec.h"
#include "terralod/format/tileset_format.h"
#include "terralod/format/tileset_writer.h"

namespace terralod {

struct ChunkPassOptions {
  int32_t blockCells = 512;
  unsigned threads = 1;
  int compressionLevel = kDefaultChunkCompressionLevel;
  const TextureBuild* textures = nullptr;  ///< null: geometry only
};

/// Breadth-first node list of the tree (roots row-major, children SW, SE, NW, NE).
std::vector<NodeRecord> enumerateNodes(const TreeLayout& layout);

/// Builds every node's chunk and appends its blob to `writer` (with its texture blob right
/// after it when `options.textures` is set), filling in the node records.
/// Exactly one of `allHeights` (in-memory raster) and `sparse` (streamed raster, recorded
/// into during this pass) is non-null; `windows` serves the blocks in the streamed case.
Status buildChunks(const TreeLayout& layout, const ErrorBudget& budget, const ActivationGrid& grid,
                   std::vector<NodeRecord>& nodes, HeightWindows& windows,
                   const HeightSampler* allHeights, SparseHeights* sparse,
                   const ChunkPassOptions& options, TilesetWriter& writer, Progress& progress);

}  // namespace terralod
