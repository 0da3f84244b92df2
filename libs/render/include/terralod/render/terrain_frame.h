#pragma once
// One frame as the chunk kinds of the GL renderer see it (DrawnChunkKind<TerrainFrame>): the
// frame context every pass shares (camera matrices, viewport, style, depth), the tree, and what
// was drawn. Kinds add their opaque draws between TerrainRenderer::beginFrame (clear, sky) and
// finishFrame (composited layers, overlays). Render thread only.

#include "terralod/render/frame_context.h"
#include "terralod/render/terrain_renderer.h"
#include "terralod/runtime/chunk_tree.h"
#include "terralod/runtime/selection.h"

namespace terralod {

struct TerrainFrame {
  const FrameContext& context;
  const ChunkTree& tree;
  DrawStats& stats;  ///< what the kinds drew into the frame, added up
  /// τ and morphing as the selection used them (kinds that pick their own level of detail,
  /// e.g. VIPM chunks, follow them); drawable is unused.
  SelectionOptions selection;
};

}  // namespace terralod
