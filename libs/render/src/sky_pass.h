#pragma once
// The sky: a full-screen triangle at infinite distance behind everything, from the haze colour
// at the horizon to the background colour overhead. Render thread only.

#include <cstdint>

#include "gl_object.h"
#include "terralod/core/result.h"
#include "terralod/render/frame_context.h"
#include "terralod/render/shader_program.h"

namespace terralod {

class SkyPass {
 public:
  static Result<SkyPass> create();
  /// Draws the sky with the depth test off; returns the draw calls (1).
  uint32_t draw(const FrameContext& frame) const;

 private:
  explicit SkyPass(ShaderProgram program);
  ShaderProgram mProgram;
  GlVertexArray mEmpty;  // core profile draws need a vertex array, even without attributes
};

}  // namespace terralod
