#include "chunk_box_pass.h"

#include <epoxy/gl.h>

#include <glm/gtc/type_ptr.hpp>

#include "terrain_shaders.h"

namespace terralod {

Result<ChunkBoxPass> ChunkBoxPass::create() {
  auto program = ShaderProgram::create(
      "boxes", {shaders::kBoxVertex, shaders::withLevelPalette(shaders::kBoxFragment), {}});
  if (!program) return program.error();
  return ChunkBoxPass(std::move(program).value());
}

ChunkBoxPass::ChunkBoxPass(ShaderProgram program)
    : mProgram(std::move(program)), mVertexArray(GlVertexArray::make()) {
  const GLuint vao = mVertexArray.id();
  glVertexArrayAttribFormat(vao, 0, 3, GL_FLOAT, GL_FALSE, 0);
  glVertexArrayAttribFormat(vao, 1, 1, GL_FLOAT, GL_FALSE, 3 * sizeof(float));
  glVertexArrayAttribBinding(vao, 0, 0);
  glVertexArrayAttribBinding(vao, 1, 0);
  glEnableVertexArrayAttrib(vao, 0);
  glEnableVertexArrayAttrib(vao, 1);
}

uint32_t ChunkBoxPass::draw(const FrameContext& frame, const ChunkTree& tree,
                            std::span<const SelectedChunk> selection, const GpuChunkStore& store) {
  mStaging.clear();
  const glm::dvec3 eye = frame.eye;
  for (const SelectedChunk& s : selection) {
    if (!store.find(s.node)) continue;
    const ChunkNode& n = tree.node(s.node);
    const glm::dvec3 lo(n.box.min[0], n.box.min[1], n.box.min[2]);
    const glm::dvec3 hi(n.box.max[0], n.box.max[1], n.box.max[2]);
    auto corner = [&](int i) {
      return glm::vec3(glm::dvec3(i & 1 ? hi.x : lo.x, i & 2 ? hi.y : lo.y, i & 4 ? hi.z : lo.z) -
                       eye);
    };
    // The 12 edges: corners differing in one coordinate bit.
    for (int a = 0; a < 8; ++a)
      for (int bit = 1; bit < 8; bit <<= 1) {
        if (a & bit) continue;
        for (const glm::vec3 p : {corner(a), corner(a | bit)})
          mStaging.insert(mStaging.end(), {p.x, p.y, p.z, float(n.level)});
      }
  }
  if (mStaging.empty()) return 1;
  mLines.upload(mStaging);
  glVertexArrayVertexBuffer(mVertexArray.id(), 0, mLines.id(), 0, 4 * sizeof(float));
  glBindVertexArray(mVertexArray.id());
  mProgram.use();
  glProgramUniformMatrix4fv(mProgram.id(), mProgram.uniformLocation("uViewProjection"), 1, GL_FALSE,
                            glm::value_ptr(frame.viewProjection));
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_GEQUAL);
  glDrawArrays(GL_LINES, 0, GLsizei(mStaging.size() / 4));
  return 1;
}

}  // namespace terralod
