#include "sky_pass.h"

#include <glm/gtc/type_ptr.hpp>
#include <glm/mat4x4.hpp>

#include "atmosphere.h"
#include "frame_colors.h"
#include "terrain_shaders.h"

namespace terralod {

Result<SkyPass> SkyPass::create() {
  auto program = ShaderProgram::create("sky", {shaders::kSkyVertex, shaders::skyFragment(), {}});
  if (!program) return program.error();
  return SkyPass(std::move(program).value());
}

SkyPass::SkyPass(ShaderProgram program)
    : mProgram(std::move(program)), mEmpty(GlVertexArray::make()) {}

uint32_t SkyPass::draw(const FrameContext& frame, double floor) const {
  const glm::vec3 background = backgroundColor(frame.style);
  const glm::vec3 haze = hazeColor(frame.style);
  glDisable(GL_DEPTH_TEST);
  glBindVertexArray(mEmpty.id());
  mProgram.use();
  const glm::mat4 inverse(glm::inverse(frame.projection * frame.viewRotation));
  glUniformMatrix4fv(mProgram.uniformLocation("uInverseViewProjection"), 1, GL_FALSE,
                     glm::value_ptr(inverse));
  glUniform3fv(mProgram.uniformLocation("uBackground"), 1, glm::value_ptr(background));
  glUniform3fv(mProgram.uniformLocation("uHaze"), 1, glm::value_ptr(haze));
  glUniform1f(mProgram.uniformLocation("uEyeHeight"), float(frame.eye.z));
  glUniform1f(mProgram.uniformLocation("uFloor"), float(floor));
  glUniform1f(mProgram.uniformLocation("uScaleHeight"), float(kScaleHeight));
  glUniform1f(mProgram.uniformLocation("uExtinction"), float(extinction(frame.style)));
  glDrawArrays(GL_TRIANGLES, 0, 3);
  return 1;
}

}  // namespace terralod
