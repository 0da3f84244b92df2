#pragma once
// A depth buffer as a texture that later render passes can sample (frame_context.h).

#include <cstdint>

namespace terralod {

/// A depth buffer that shaders may read: reversed-Z, 1 at the near plane and 0 at infinity
/// (clear value 0), 32-bit float. `samples` 0: a GL_TEXTURE_2D (sampler2D); more: a
/// GL_TEXTURE_2D_MULTISAMPLE (sampler2DMS, texelFetch per sample). texture 0: the target has
/// no readable depth (a window's default framebuffer).
struct DepthTexture {
  uint32_t texture = 0;
  int samples = 0;
  bool readable() const { return texture != 0; }
};

}  // namespace terralod
