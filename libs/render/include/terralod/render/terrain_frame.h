#pragma once
// One frame as the chunk kinds of the GL renderer see it (DrawnChunkKind<TerrainFrame>): the
// view, the tree, the style, and what was drawn. Render thread only.

#include "terralod/render/terrain_renderer.h"
#include "terralod/runtime/chunk_tree.h"
#include "terralod/runtime/view.h"

namespace terralod {

struct TerrainFrame {
  const View& view;
  const ChunkTree& tree;
  const TerrainStyle& style;
  DrawStats stats;  ///< what the kinds drew into the frame
};

}  // namespace terralod
