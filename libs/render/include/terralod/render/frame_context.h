#pragma once
// What every render pass of one frame shares: the camera's matrices, the viewport, the style
// and the depth the opaque terrain wrote, as a texture later passes (composited layers) can
// sample. Positions given to the matrices are relative to the eye (the eye is the origin), so
// float keeps millimetres far from the data's origin; the eye itself is kept in double.

#include <cstdint>

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include "terralod/render/depth_texture.h"
#include "terralod/render/terrain_style.h"
#include "terralod/runtime/view.h"

namespace terralod {

/// The near plane of the projection, metres. Reversed depth keeps precision far away.
inline constexpr double kNearPlane = 0.05;

struct Viewport {
  int x = 0, y = 0;
  int width = 0, height = 0;
};

struct FrameContext {
  View view;
  glm::dvec3 eye{0.0};           ///< metres, the data's coordinates
  glm::dmat4 viewRotation{1.0};  ///< world directions to camera space (no translation)
  /// Infinite perspective with reversed depth for clip control GL_ZERO_TO_ONE: depth
  /// kNearPlane / distance along the view axis.
  glm::dmat4 projection{1.0};
  glm::mat4 viewProjection{1.0};  ///< projection * viewRotation, for eye-relative positions
  Viewport viewport;
  TerrainStyle style;
  DepthTexture depth;
};

/// The frame context of `view` drawn in `style` into a target whose depth is `depth`; the
/// viewport covers the view's width and height.
FrameContext makeFrameContext(const View& view, const TerrainStyle& style, DepthTexture depth);

/// The depth texture attached to the bound draw framebuffer; none for the default framebuffer
/// or a depth renderbuffer. Needs a current GL context.
DepthTexture boundDepthTexture();

}  // namespace terralod
