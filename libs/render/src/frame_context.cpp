#include "terralod/render/frame_context.h"

#include <epoxy/gl.h>

#include <glm/gtc/matrix_transform.hpp>

namespace terralod {
namespace {

// An infinite reversed-depth perspective (depth 1 at the near plane, 0 at infinity), with
// clip control set to [0, 1]: precision is spread evenly in log distance.
glm::dmat4 reversedInfinitePerspective(const View& v) {
  glm::dmat4 p(0.0);
  p[0][0] = 1.0 / v.tanHalfWidth;
  p[1][1] = 1.0 / v.tanHalfHeight;
  p[2][3] = -1.0;
  p[3][2] = kNearPlane;
  return p;
}

}  // namespace

FrameContext makeFrameContext(const View& view, const TerrainStyle& style, DepthTexture depth) {
  FrameContext frame;
  frame.view = view;
  frame.eye = view.camera.eye;
  // World to camera rotation (the eye is the origin of the positions the shaders see).
  frame.viewRotation = glm::lookAt(glm::dvec3(0.0), view.forward, view.up);
  frame.projection = reversedInfinitePerspective(view);
  frame.viewProjection = glm::mat4(frame.projection * frame.viewRotation);
  frame.viewport = {0, 0, view.camera.width, view.camera.height};
  frame.style = style;
  frame.depth = depth;
  return frame;
}

DepthTexture boundDepthTexture() {
  GLint framebuffer = 0;
  glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &framebuffer);
  if (framebuffer == 0) return {};
  GLint type = GL_NONE;
  glGetNamedFramebufferAttachmentParameteriv(GLuint(framebuffer), GL_DEPTH_ATTACHMENT,
                                             GL_FRAMEBUFFER_ATTACHMENT_OBJECT_TYPE, &type);
  if (type != GL_TEXTURE) return {};
  GLint name = 0;
  glGetNamedFramebufferAttachmentParameteriv(GLuint(framebuffer), GL_DEPTH_ATTACHMENT,
                                             GL_FRAMEBUFFER_ATTACHMENT_OBJECT_NAME, &name);
  GLint samples = 0;
  glGetTextureLevelParameteriv(GLuint(name), 0, GL_TEXTURE_SAMPLES, &samples);
  return {uint32_t(name), samples};
}

}  // namespace terralod
