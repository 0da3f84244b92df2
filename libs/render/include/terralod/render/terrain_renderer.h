#pragma once
// Draws a frame of terrain as passes over one frame context (frame_context.h): the sky, the
// opaque terrain (one multi-draw-indirect call per texture array pair; gl_DrawIDARB picks each
// draw's placement; the morph in the vertex shader), the composited layers added to it
// (composited_layer.h), then the overlays (wireframe, chunk boxes). Render thread only; create
// and destroy it where its GlContext is current.

#include <cstdint>
#include <memory>
#include <span>

#include "terralod/core/result.h"
#include "terralod/render/composited_layer.h"
#include "terralod/render/frame_context.h"
#include "terralod/render/gpu_chunk_store.h"
#include "terralod/render/terrain_style.h"
#include "terralod/runtime/chunk_tree.h"
#include "terralod/runtime/selection.h"
#include "terralod/runtime/view.h"

namespace terralod {

struct DrawStats {
  uint32_t chunks = 0;        ///< selected chunks that were on the GPU and drawn
  uint32_t missing = 0;       ///< selected chunks not in the store (skipped)
  uint32_t drawCalls = 0;     ///< GL draw calls issued (multi-draws count once)
  uint32_t drawCommands = 0;  ///< indirect commands in them
  uint64_t triangles = 0;     ///< triangles drawn, skirts included when on
  /// Vertices drawn: a VIPM chunk's active vertices (flanges left out), a static chunk's part
  /// vertices before its skirt's.
  uint64_t vertices = 0;
  uint32_t blots = 0;  ///< VIPM chunks drawn as blots (one pass, vipm_blot.h)
  /// VIPM super-chunk calls (each the blots of one block, two or more) and the blots in them.
  uint32_t superChunks = 0;
  uint32_t superChunkBlots = 0;
};

class TerrainRenderer {
 public:
  /// Compiles the shaders.
  static Result<TerrainRenderer> create();
  ~TerrainRenderer();
  TerrainRenderer(TerrainRenderer&& other) noexcept;
  TerrainRenderer& operator=(TerrainRenderer&&) = delete;
  TerrainRenderer(const TerrainRenderer&) = delete;
  TerrainRenderer& operator=(const TerrainRenderer&) = delete;

  /// The tileset's texture sizes per level (root first), for sampling mips where the builder
  /// put their texels (texture_placement.h). Without them GL's own sampling is used.
  void setTextureSizes(std::span<const uint32_t> colorSizes, std::span<const uint32_t> normalSizes);
  /// The snow line the shader's generated colour uses (TilesetMetadata::snowLine, version 6).
  void setSnowLine(std::span<const float> samples, uint32_t lastRow, double spacingY);

  /// Adds a layer drawn after the opaque terrain of every frame, after the layers added
  /// before it; returns it.
  CompositedLayer& addLayer(std::unique_ptr<CompositedLayer> layer);

  // A frame in stages, for a caller that draws more than one kind of chunk (TerrainScene):
  // beginFrame, then each kind's opaque draws (drawStaticChunks for static chunks), then
  // finishFrame. draw() below is the three for static chunks alone.

  /// Clears the bound framebuffer (viewport: the view's size) and draws the sky; returns the
  /// frame context the other stages draw with (its depth: the bound target's depth texture).
  FrameContext beginFrame(const View& view, const TerrainStyle& style, const ChunkTree& tree,
                          DrawStats& stats);
  /// The opaque pass of the static chunks among `chunks` that `store` holds, and their
  /// wireframe overlay when the style asks for it.
  void drawStaticChunks(const FrameContext& frame, const ChunkTree& tree,
                        std::span<const SelectedChunk> chunks, const GpuChunkStore& store,
                        DrawStats& stats);
  /// The composited layers over the opaque terrain, then the chunk-box overlay of `selection`
  /// (those `store` holds); leaves the GL state as the frame found it.
  void finishFrame(const FrameContext& frame, const ChunkTree& tree,
                   std::span<const SelectedChunk> selection, const GpuChunkStore& store,
                   DrawStats& stats);

  /// A whole frame of static chunks: the selected chunks of `tree` that `store` holds.
  DrawStats draw(const View& view, const ChunkTree& tree, std::span<const SelectedChunk> selection,
                 const GpuChunkStore& store, const TerrainStyle& style);

 private:
  struct Passes;
  explicit TerrainRenderer(std::unique_ptr<Passes> passes);
  std::unique_ptr<Passes> mPasses;
};

}  // namespace terralod
