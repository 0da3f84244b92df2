#include "sky_pass.h"

#include <glm/gtc/type_ptr.hpp>
#include <glm/mat4x4.hpp>

#include "frame_colors.h"
#include "terrain_shaders.h"

namespace terralod {

Result<SkyPass> SkyPass::create() {
  auto program = ShaderProgram::create("sky", {shaders::kSkyVertex, shaders::kSkyFragment, {}});
  if (!program) return program.error();
  return SkyPass(std::move(program).value());
}

SkyPass::SkyPass(ShaderProgram program)
    : mProgram(std::move(program)), mEmpty(GlVertexArray::make()) {}

uint32_t SkyPass::draw(const FrameContext& frame) const {
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
  glDrawArrays(GL_TRIANGLES, 0, 3);
  return 1;
}

}  // namespace terralod
