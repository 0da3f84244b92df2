#pragma once
// The chunk-box overlay: each drawn chunk's bounding box as lines, coloured by its level like
// --color-by level, depth-tested against the terrain. Render thread only.

#include <cstdint>
#include <span>
#include <vector>

#include "gl_object.h"
#include "terralod/core/result.h"
#include "terralod/render/frame_context.h"
#include "terralod/render/gpu_chunk_store.h"
#include "terralod/render/shader_program.h"
#include "terralod/runtime/chunk_tree.h"
#include "terralod/runtime/selection.h"

namespace terralod {

class ChunkBoxPass {
 public:
  static Result<ChunkBoxPass> create();
  /// Outlines the selected chunks `store` holds; returns the draw calls (1, even when none
  /// is held, as the renderer has always counted it).
  uint32_t draw(const FrameContext& frame, const ChunkTree& tree,
                std::span<const SelectedChunk> selection, const GpuChunkStore& store);

 private:
  explicit ChunkBoxPass(ShaderProgram program);
  ShaderProgram mProgram;
  GlVertexArray mVertexArray;
  GrowingBuffer mLines;
  std::vector<float> mStaging;  // x, y, z relative to the eye, then the level, per vertex
};

}  // namespace terralod
