#pragma once
// The sky: a full-screen triangle at infinite distance behind everything, the background colour
// seen through the air each pixel's ray crosses (atmosphere.h): haze at the horizon. Render thread
// only.

#include <cstdint>

#include "gl_object.h"
#include "terralod/core/result.h"
#include "terralod/render/frame_context.h"
#include "terralod/render/shader_program.h"

namespace terralod {

class SkyPass {
 public:
  static Result<SkyPass> create();
  /// Draws the sky with the depth test off; returns the draw calls (1). Rays looking down end
  /// at `floor` (metres; the lower of sea level and the data's lowest point).
  uint32_t draw(const FrameContext& frame, double floor) const;

 private:
  explicit SkyPass(ShaderProgram program);
  ShaderProgram mProgram;
  GlVertexArray mEmpty;  // core profile draws need a vertex array, even without attributes
};

}  // namespace terralod
