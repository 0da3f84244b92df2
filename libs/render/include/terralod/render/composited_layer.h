#pragma once
// The hook for what is drawn over the opaque terrain with correct depth (a vegetation layer,
// markers): TerrainRenderer draws its layers after the sky and the terrain, before the
// overlays (wireframe, chunk boxes), in the order they were added.

#include <cstdint>

#include "terralod/render/frame_context.h"

namespace terralod {

/// Render thread only, like the renderer that draws it.
class CompositedLayer {
 public:
  virtual ~CompositedLayer() = default;

  /// Draws the layer; returns the GL draw calls it issued. On entry the frame's framebuffer
  /// is bound with its viewport and clip control GL_ZERO_TO_ONE; the depth test is on with
  /// GL_GEQUAL (reversed-Z: nearer is greater) against the opaque terrain's depth; depth
  /// writes, blending and face culling are off. frame.depth, when readable, holds that depth
  /// and nothing writes it while depth writes stay off, so the layer may sample it (a layer
  /// that turns depth writes on must not sample it in the same draw, and must call
  /// glTextureBarrier() before reading what it wrote). The layer binds its own program,
  /// vertex array and textures, and leaves depth writes, blending and culling off.
  virtual uint32_t draw(const FrameContext& frame) = 0;
};

}  // namespace terralod
