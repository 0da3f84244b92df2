#pragma once
// The second pass of the build: meshing, encoding and writing every chunk.
//
// Work is split by blocks (the chunk squares of the level whose side is blockCells): each
// block's window of heights is read once and every chunk below that level inside it is built
// from it. Chunks at the block level and above (few, large, sparse) come last, from heights
// that are either the whole raster (when it is in memory) or the SparseHeights recorded by the
// blocks. Blobs are written in a fixed order, so the file does not depend on thread timing.

#include <functional>
#include <memory>
#include <span>
#include <utility>
#include <vector>

#include "terralod/build/activation_grid.h"
#include "terralod/build/chunk_mesher.h"
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

/// How static builds store chunks unless asked otherwise: RTIN chunks as their bintree
/// (payload version 3, file version 7), greedy ones with skirts derived by the reader (2).
inline constexpr ChunkPayloadVersion kStaticChunkPayload = ChunkPayloadVersion::kRtinCoded;

struct ChunkPassOptions {
  int32_t blockCells = 512;
  unsigned threads = 1;
  int compressionLevel = kDefaultChunkCompressionLevel;
  const TextureBuild* textures = nullptr;  ///< null: geometry only (or textures made already)
  /// Textures made before this pass (PassOneTextures): every node's blob by node index, empty
  /// for one that inherits its parent's; taken as the chunks are written. With `textures` null.
  std::vector<std::vector<uint8_t>>* madeTextures = nullptr;
  MeshMethod mesher = MeshMethod::kRtin;
  ChunkPayloadVersion payload = kStaticChunkPayload;
};

/// Breadth-first node list of the tree (roots row-major, children SW, SE, NW, NE).
std::vector<NodeRecord> enumerateNodes(const TreeLayout& layout);

/// The level whose chunks are the blocks (chunk squares of side blockCells).
int32_t blockLevelOf(const TreeLayout& layout, int32_t blockCells);
/// The block-level nodes in node order (the order blocks' chunks are written in), and every
/// node at that level or above (built after them, from sparse heights).
std::vector<uint32_t> blockNodesOf(const std::vector<NodeRecord>& nodes, int32_t blockLevel);
std::vector<uint32_t> coarseNodesOf(const std::vector<NodeRecord>& nodes, int32_t blockLevel);

/// One chunk's stored bytes: its mesh blob and (textured builds) its texture blob.
struct BuiltChunk {
  uint32_t node = 0;
  std::vector<uint8_t> blob, texture;
};

/// What one block's part of pass 2 makes: every chunk below the block node inside it, in
/// writing order, and what the coarser levels will need from it.
struct BlockChunks {
  std::vector<BuiltChunk> chunks;
  ChunkTiles tiles;                   ///< the block node's texture tiles (textured builds)
  std::vector<uint8_t> blockTexture;  ///< the block node's texture blob
  /// Heights of the points whose activation reaches the block level (inside the data).
  std::vector<std::pair<uint64_t, float>> points;
};

/// The parts of the build every block shares.
struct ChunkPassContext {
  const TreeLayout& layout;
  const ErrorBudget& budget;
  std::vector<NodeRecord>& nodes;  ///< statistics of built nodes are filled in
  int32_t blockCells = 512;
  int compressionLevel = kDefaultChunkCompressionLevel;
  TexturePass* textures = nullptr;        ///< null: geometry only
  MeshMethod mesher = MeshMethod::kRtin;  ///< below the block level (the levels above: RTIN)
  ChunkPayloadVersion payload = kStaticChunkPayload;
  /// The first level `mesher` meshes: the one below the blocks, or 0 where the coarse pass
  /// has every height too (firstGreedyLevel()).
  int32_t firstGreedyLevel = 0;
};

/// What the coarse pass (the block level and above) meshes from: every height (a local build
/// that read the raster whole) or the sparse ones pass 1 kept (streamed and staged builds).
enum class CoarseHeights : uint8_t { kSparse, kEvery };

/// The first level a greedy build meshes by insertion: the one below the block level, or the
/// roots when the coarse pass has every height (it then meshes the levels at and above the
/// blocks first, top down, and the blocks' chunks start from them); with sparse heights the
/// levels at and above the blocks stay RTIN.
int32_t firstGreedyLevel(int32_t blockLevel, CoarseHeights heights);

/// A block's heights as read once for both of its passes: the (cells + 1)² samples from
/// (x0, y0), and around them `margin` more on every side, which the texture pass reads
/// (BlockTexels::kMargin; 0 without textures). Rows of stride() samples.
struct BlockWindow {
  std::vector<float> values;
  int32_t x0 = 0, y0 = 0, cells = 0, margin = 0;

  int32_t stride() const { return cells + 1 + 2 * margin; }
  /// The height at grid point (x, y), within the margin.
  float at(int32_t x, int32_t y) const {
    return values[size_t(y - y0 + margin) * size_t(stride()) + size_t(x - x0 + margin)];
  }
};

/// Reads block (x0, y0)'s `cells` window into `window`, with the texture pass's margin when
/// `context` makes textures.
Status readBlockWindow(const ChunkPassContext& context, HeightWindows& windows, int32_t x0,
                       int32_t y0, int32_t cells, BlockWindow& window, unsigned worker);

/// Builds the chunks below block node `blockNode` from its `window` of heights (null: the
/// mesher already has every height), with `mesher` (whose activation grid covers the block).
/// The texture pass takes its heights from the window too, and from `windows` without one;
/// `worker` names the calling thread.
Result<BlockChunks> buildBlockChunks(const ChunkPassContext& context, uint32_t blockNode,
                                     const BlockWindow* window, ChunkMesher& mesher,
                                     const ActivationGrid& grid, HeightWindows& windows,
                                     unsigned worker);

/// The chunks below block node `blockNode`, in the order buildBlockChunks makes them
/// (breadth first).
std::vector<uint32_t> chunksBelow(const std::vector<NodeRecord>& nodes, uint32_t blockNode);

/// The texture pass over block node `blockNode` from its margined `window` alone (a staged
/// build's pass 1 makes textures from the window it reads): the block node's tiles, and the
/// blobs of it and of every node below it into `blobs`.
Result<ChunkTiles> blockTexturesFrom(TexturePass& textures, uint32_t blockNode,
                                     const BlockWindow& window, unsigned worker,
                                     std::vector<std::pair<uint32_t, std::vector<uint8_t>>>& blobs);

/// Encoded texture blobs by node.
using NodeTextures = std::vector<std::pair<uint32_t, std::vector<uint8_t>>>;

/// Builds every chunk at the block level and above (`coarseNodes`, in that order), with one
/// mesher per thread over the coarse heights. Returns the chunks in `coarseNodes` order,
/// without textures: those above the block level come from a TilePyramid.
Result<std::vector<BuiltChunk>> buildCoarseChunks(
    const ChunkPassContext& context, const std::vector<uint32_t>& coarseNodes,
    std::vector<std::unique_ptr<ChunkMesher>>& meshers, Progress& progress);
/// The same, level by level from the roots (`coarseNodes` breadth-first), each level's chunks
/// starting from their parents' surfaces, which go into `surfaces` (and the meshers read them
/// from there from now on): a greedy build's coarse levels, from every height.
Result<std::vector<BuiltChunk>> buildCoarseChunksTopDown(
    const ChunkPassContext& context, const std::vector<uint32_t>& coarseNodes,
    std::vector<std::unique_ptr<ChunkMesher>>& meshers, SurfaceStore& surfaces, Progress& progress);
/// Gives each chunk its blob in `textures` (consumed); an internal error when one has none.
Status attachTextures(std::vector<BuiltChunk>& chunks, NodeTextures textures,
                      const std::vector<NodeRecord>& nodes);

/// Appends a chunk's blobs to the file and records where they went in its node.
Status appendChunk(TilesetWriter& writer, NodeRecord& node, std::span<const uint8_t> blob,
                   std::span<const uint8_t> texture);

/// Meshes, quantises and encodes one chunk; fills in its node's statistics.
Result<std::vector<uint8_t>> buildChunk(ChunkMesher& mesher, const ErrorBudget& budget,
                                        NodeRecord& node, int compressionLevel,
                                        ChunkPayloadVersion payload);

/// Builds every node's chunk and appends its blob to `writer` (with its texture blob right
/// after it when `options.textures` is set), filling in the node records.
/// Exactly one of `allHeights` (in-memory raster) and `sparse` (streamed raster, recorded
/// into during this pass) is non-null; `windows` serves the blocks in the streamed case.
Status buildChunks(const TreeLayout& layout, const ErrorBudget& budget, const ActivationGrid& grid,
                   std::vector<NodeRecord>& nodes, HeightWindows& windows,
                   const HeightSampler* allHeights, SparseHeights* sparse,
                   const ChunkPassOptions& options, TilesetWriter& writer, Progress& progress);

}  // namespace terralod
