#pragma once
// A tileset ready to draw: the reader, its chunk tree, the chunks on the GPU and the renderer,
// with one call per frame (select, bring missing chunks to the GPU, draw). What `render`,
// `bench` and the viewer share. Render thread only.
//
// Chunks are read and decoded on the render thread when a selection first needs them; the
// out-of-core loader (issue 5) replaces that with worker threads and a memory budget.

#include <chrono>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "terralod/format/tileset_reader.h"
#include "terralod/render/gpu_chunk_store.h"
#include "terralod/render/terrain_renderer.h"
#include "terralod/runtime/chunk_tree.h"
#include "terralod/runtime/selection.h"

namespace terralod {

struct FrameStats {
  SelectionStats selection;
  DrawStats draw;
  double selectMicroseconds = 0;
  double loadMilliseconds = 0;    ///< reading, decoding and uploading chunks this frame
  double uploadMilliseconds = 0;  ///< of which copying to the GPU
  uint32_t loads = 0;             ///< chunks brought to the GPU this frame
};

class TerrainScene {
 public:
  /// Takes the opened tileset. A GlContext must be current.
  static Result<std::unique_ptr<TerrainScene>> create(std::unique_ptr<TilesetReader> tileset);

  /// Selects for `view`, loads what is missing and draws into the bound framebuffer. Fails
  /// when a chunk cannot be read (naming it); nothing is drawn then. With `reselect` false the
  /// last frame's selection and morph parameters are drawn again from the new view (the
  /// viewer's "freeze selection", to look at what was chosen from elsewhere).
  Result<FrameStats> renderFrame(const View& view, const SelectionOptions& selection,
                                 const TerrainStyle& style, bool reselect = true);

  /// Draws the given chunks (with their morph parameters) from `view`, loading what is
  /// missing: for comparing two selections from one camera.
  Result<FrameStats> drawChunks(const View& view, std::span<const SelectedChunk> chunks,
                                const TerrainStyle& style);

  const ChunkTree& tree() const { return mTree; }
  const GpuChunkStore& store() const { return mStore; }
  const TilesetReader& tileset() const { return *mTileset; }
  /// The chunks the last frame selected.
  const std::vector<SelectedChunk>& selected() const { return mSelected; }
  uint64_t gpuBytes() const { return mStore.residentBytes(); }

 private:
  TerrainScene(std::unique_ptr<TilesetReader> tileset, ChunkTree tree, TerrainRenderer renderer);
  Status load(std::span<const SelectedChunk> chunks, FrameStats& stats);

  std::unique_ptr<TilesetReader> mTileset;
  ChunkTree mTree;
  GpuChunkStore mStore;
  TerrainRenderer mRenderer;
  std::vector<SelectedChunk> mSelected;
  SelectionStats mLastSelection;
};

}  // namespace terralod
