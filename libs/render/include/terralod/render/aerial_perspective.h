#pragma once
// The terrain's aerial perspective for composited layers (composited_layer.h) that draw things
// standing on it, so they fade into the haze exactly as the ground under them does.

#include <cstdint>
#include <string>

#include "terralod/render/frame_context.h"

namespace terralod {

/// GLSL to paste after a shader's version line: the atmosphere's uniforms and
///   vec3 hazed(vec3 linearColour, float height, float distance)
/// the colour of something `distance` metres from the eye at `height` metres, seen through the
/// air (linear colour in and out, as the terrain's shader computes it).
std::string aerialPerspectiveGlsl();

/// Sets those uniforms of `program` for `frame`.
void setAerialPerspective(uint32_t program, const FrameContext& frame);

}  // namespace terralod
