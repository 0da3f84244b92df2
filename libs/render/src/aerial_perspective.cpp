#include "terralod/render/aerial_perspective.h"

#include <epoxy/gl.h>

#include <glm/gtc/type_ptr.hpp>

#include "atmosphere.h"
#include "frame_colors.h"
#include "terrain_shaders.h"

namespace terralod {

std::string aerialPerspectiveGlsl() {
  return std::string(shaders::kAtmosphere) + R"(
uniform vec3 uHaze;        // the air's colour, linear
uniform float uEyeHeight;  // metres
vec3 hazed(vec3 color, float height, float distance) {
  float through = transmittance(uEyeHeight, height, distance);
  return color * through + uHaze * (1.0 - through);
}
)";
}

void setAerialPerspective(uint32_t program, const FrameContext& frame) {
  const glm::vec3 haze = glm::pow(hazeColor(frame.style), glm::vec3(2.2f));
  glProgramUniform3fv(program, glGetUniformLocation(program, "uHaze"), 1, glm::value_ptr(haze));
  glProgramUniform1f(program, glGetUniformLocation(program, "uEyeHeight"), float(frame.eye.z));
  glProgramUniform1f(program, glGetUniformLocation(program, "uScaleHeight"), float(kScaleHeight));
  glProgramUniform1f(program, glGetUniformLocation(program, "uExtinction"),
                     float(extinction(frame.style)));
}

}  // namespace terralod
