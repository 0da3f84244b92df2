#pragma once
// The opaque terrain: the selected chunks as one multi-draw-indirect call per texture array
// pair and sampling variant (gl_DrawIDARB picks each draw's placement), the morph in the
// vertex shader. The same draws again as lines make the wireframe overlay. Render thread only.

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "gl_object.h"
#include "terralod/core/result.h"
#include "terralod/render/frame_context.h"
#include "terralod/render/gpu_chunk_store.h"
#include "terralod/render/shader_program.h"
#include "terralod/render/terrain_renderer.h"
#include "terralod/runtime/chunk_tree.h"
#include "terralod/runtime/selection.h"

namespace terralod {

/// What a terrain draw paints: the lit surface, or its triangle edges over it.
enum class TerrainDrawMode { kSurface, kWireframe };

class TerrainPass {
 public:
  static Result<TerrainPass> create();

  /// texture_placement.h: where each level's mips keep their texels.
  void setTextureSizes(std::span<const uint32_t> colorSizes, std::span<const uint32_t> normalSizes);
  /// Shade layers: the tileset's snow line samples (TilesetMetadata::snowLine) from row 0 to
  /// `lastRow`, rows `spacingY` metres apart.
  void setSnowLine(std::span<const float> samples, uint32_t lastRow, double spacingY);

  /// Gathers the frame's draws (the selected chunks `store` holds) and uploads them; counts
  /// chunks, missing chunks, commands and triangles (no draw calls yet).
  DrawStats prepare(const FrameContext& frame, const ChunkTree& tree,
                    std::span<const SelectedChunk> selection, const GpuChunkStore& store);
  /// True when prepare() found something to draw.
  bool empty() const { return mPending.empty(); }
  /// Draws what prepare() gathered; returns the draw calls. kSurface tests and writes depth
  /// (GL_GREATER); kWireframe draws lines pulled a little towards the eye over it.
  uint32_t draw(const FrameContext& frame, const ChunkTree& tree, const GpuChunkStore& store,
                TerrainDrawMode mode);

 private:
  explicit TerrainPass(std::vector<ShaderProgram> programs);
  void setFrameUniforms(const FrameContext& frame, const ChunkTree& tree);
  uint32_t drawGroups(const GpuChunkStore& store, TerrainDrawMode mode);

  // The program for each variant: the piecewise mask (mPiecewise's bits), 4 with a shade layer.
  std::vector<ShaderProgram> mPrograms;
  GlVertexArray mVertexArray;
  GlBuffer mPlacementBuffer;
  GrowingBuffer mDrawBuffer, mIndirectBuffer;
  // Per level (root first): bit 0 when its colour mips need piecewise sampling, bit 1 its
  // normal mips. Draws are grouped by it and drawn with the program variant for it.
  std::vector<uint8_t> mPiecewise;
  std::vector<float> mSnowLine;  // kSnowLineSamples values
  float mSnowFraction = 0;
  // Per-frame staging, kept to avoid allocating once they are big enough.
  struct PendingDraw {
    uint64_t group = 0;    // colour array << 32 | normal array; all ones: untextured
    uint32_t variant = 0;  // mPiecewise of the owner's level, | 4 for a shade layer
    uint32_t colorSize = 0, normalSize = 0;
    std::array<float, 16> draw{};
    std::array<uint32_t, 5> command{};
  };
  std::vector<PendingDraw> mPending;
  std::vector<float> mDraws;
  std::vector<uint32_t> mCommands;
};

}  // namespace terralod
