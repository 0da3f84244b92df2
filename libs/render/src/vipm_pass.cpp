#include "vipm_pass.h"

#include <epoxy/gl.h>

#include <algorithm>
#include <cmath>
#include <glm/gtc/type_ptr.hpp>
#include <numbers>

#include "atmosphere.h"
#include "frame_colors.h"
#include "terralod/materials/detail_texture.h"
#include "terralod/vipm/vipm_blot.h"
#include "vipm_shaders.h"

namespace terralod {
namespace {

constexpr int kDetailSize = 256;

// The material's detail texture, and its texels' linear mean (what its smallest mip shows).
GlTexture makeDetail(const TilesetMaterial& m, std::array<float, 3>& average) {
  const DetailTexture detail = makeDetailTexture(Material{m.id, m.name, m.color}, kDetailSize);
  average = linearMean(detail.rgb);
  GLuint name = 0;
  glCreateTextures(GL_TEXTURE_2D, 1, &name);
  GlTexture texture(name);
  const int levels = int(std::log2(double(kDetailSize))) + 1;
  glTextureStorage2D(name, levels, GL_SRGB8, kDetailSize, kDetailSize);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  glTextureSubImage2D(name, 0, 0, 0, kDetailSize, kDetailSize, GL_RGB, GL_UNSIGNED_BYTE,
                      detail.rgb.data());
  glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
  glGenerateTextureMipmap(name);
  glTextureParameteri(name, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
  glTextureParameteri(name, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTextureParameteri(name, GL_TEXTURE_WRAP_S, GL_REPEAT);
  glTextureParameteri(name, GL_TEXTURE_WRAP_T, GL_REPEAT);
  return texture;
}

}  // namespace

Result<VipmPass> VipmPass::create(std::span<const TilesetMaterial> materials) {
  auto program =
      ShaderProgram::create("vipm terrain", {shaders::kVipmVertex, shaders::vipmFragment(), {}});
  if (!program) return program.error();
  std::vector<GlTexture> details;
  std::vector<std::array<float, 3>> colors;
  MaterialAverages averages;
  for (const TilesetMaterial& m : materials) {
    averages.emplace_back();
    details.push_back(makeDetail(m, averages.back()));
    colors.push_back({m.color[0] / 255.0f, m.color[1] / 255.0f, m.color[2] / 255.0f});
  }
  VipmPass pass(std::move(program).value(), std::move(details), std::move(colors));
  pass.mAverages = std::move(averages);
  return pass;
}

VipmPass::VipmPass(ShaderProgram program, std::vector<GlTexture> details,
                   std::vector<std::array<float, 3>> colors)
    : mProgram(std::move(program)),
      mVertexArray(GlVertexArray::make()),
      mDetails(std::move(details)),
      mColors(std::move(colors)) {
  const GLuint vao = mVertexArray.id();
  glVertexArrayAttribFormat(vao, 0, 3, GL_FLOAT, GL_FALSE, 0);
  glVertexArrayAttribIFormat(vao, 1, 1, GL_UNSIGNED_BYTE, 0);
  // The weights of materials 0-3 and 4-7: two attributes from one 8-byte vertex.
  glVertexArrayAttribFormat(vao, 2, 4, GL_UNSIGNED_BYTE, GL_TRUE, 0);
  glVertexArrayAttribFormat(vao, 3, 4, GL_UNSIGNED_BYTE, GL_TRUE, 4);
  for (GLuint a = 0; a < 4; ++a) {
    glVertexArrayAttribBinding(vao, a, std::min(a, 2u));
    glEnableVertexArrayAttrib(vao, a);
  }
}

void VipmPass::setChunk(const ChunkTree& tree, const Draw& d) const {
  const GLuint p = mProgram.id();
  const ChunkNode& n = tree.node(d.node);
  const VipmGpuChunk& c = *d.chunk;
  const auto spacing = tree.spacing();
  // Exact positions (the vertex shader): the chunk's corner from the frame's anchor in whole
  // cells and its zBase, both exact in float, so a point two chunks share sums alike in both.
  glProgramUniform2f(p, mProgram.uniformLocation("uCornerCells"), float(c.cornerX() - mAnchor[0]),
                     float(c.cornerY() - mAnchor[1]));
  glProgramUniform1f(p, mProgram.uniformLocation("uZBase"), float(c.zBase()));
  glProgramUniform2f(p, mProgram.uniformLocation("uGridSize"), float(c.normalSize()),
                     float(c.normalSize()));
  // World-space detail coordinates, reduced to one period in double at the chunk's corner.
  std::array<float, 2> origin{};
  for (int k = 0; k < 2; ++k) {
    const double period = kDetailCells * spacing[size_t(k)];
    const double u = n.box.min[size_t(k)] / period;
    origin[size_t(k)] = float(u - std::floor(u));
  }
  glProgramUniform2f(p, mProgram.uniformLocation("uDetailOrigin"), origin[0], origin[1]);
  glProgramUniform1f(p, mProgram.uniformLocation("uLevel"), float(n.level));
  glProgramUniform1i(p, mProgram.uniformLocation("uKind"), d.blot ? 2 : n.level == 0 ? 1 : 0);
  glProgramUniform1f(p, mProgram.uniformLocation("uMorph"), d.morph);
  glVertexArrayVertexBuffer(mVertexArray.id(), 0, c.vertexBuffer(), 0, 12);
  glVertexArrayVertexBuffer(mVertexArray.id(), 1, c.materialBuffer(), 0, 1);
  glVertexArrayVertexBuffer(mVertexArray.id(), 2, c.weightBuffer(), 0, 8);
  glVertexArrayElementBuffer(mVertexArray.id(), c.indexBuffer());
  glBindTextureUnit(1, c.normalMap());
  glBindTextureUnit(2, c.blotTexture());  // blots, and the fade toward them
}

uint32_t VipmPass::drawRange(const VipmGpuChunk&, const VipmGpuChunk::Range& range) const {
  if (range.count == 0) return 0;
  glDrawElements(GL_TRIANGLES, GLsizei(range.count), GL_UNSIGNED_SHORT,
                 reinterpret_cast<const void*>(uintptr_t(range.firstIndex) * 2));
  return 1;
}

void VipmPass::draw(const FrameContext& frame, const ChunkTree& tree, std::span<const Draw> draws,
                    DrawStats& stats, VipmImage image, const VipmBlotDistances& blots) {
  if (draws.empty()) return;
  const TerrainStyle& style = frame.style;
  const GLuint p = mProgram.id();
  const double azimuth = style.sunAzimuthDegrees * std::numbers::pi / 180.0;
  const double elevation = style.sunElevationDegrees * std::numbers::pi / 180.0;
  const glm::vec3 sun(std::sin(azimuth) * std::cos(elevation),
                      std::cos(azimuth) * std::cos(elevation), std::sin(elevation));
  const glm::vec3 haze = glm::pow(hazeColor(style), glm::vec3(2.2f));
  const auto spacing = tree.spacing();
  auto at = [&](const char* name) { return mProgram.uniformLocation(name); };
  glProgramUniformMatrix4fv(p, at("uViewProjection"), 1, GL_FALSE,
                            glm::value_ptr(frame.viewProjection));
  glProgramUniform1f(p, at("uEyeHeight"), float(frame.eye.z));
  // The anchor: the grid point at a multiple of 256 cells nearest below the eye, so that
  // positions near the eye keep their precision.
  const Box& extent = tree.extent();
  const double eyeCells[2] = {(frame.eye.x - extent.min[0]) / spacing[0],
                              (frame.eye.y - extent.min[1]) / spacing[1]};
  for (int k = 0; k < 2; ++k) mAnchor[size_t(k)] = int64_t(std::floor(eyeCells[k] / 256.0)) * 256;
  glProgramUniform2f(p, at("uEyeCells"), float(eyeCells[0] - double(mAnchor[0])),
                     float(eyeCells[1] - double(mAnchor[1])));
  glProgramUniform2f(p, at("uSpacing"), float(spacing[0]), float(spacing[1]));
  glProgramUniform2f(p, at("uDetailScale"), float(1.0 / kDetailCells), float(1.0 / kDetailCells));
  glProgramUniform3fv(p, at("uSun"), 1, glm::value_ptr(sun));
  glProgramUniform3fv(p, at("uHaze"), 1, glm::value_ptr(haze));
  glProgramUniform1f(p, at("uScaleHeight"), float(kScaleHeight));
  glProgramUniform1f(p, at("uExtinction"), float(extinction(style)));
  glProgramUniform1i(p, at("uColorBy"), int(style.colorBy));
  glProgramUniform1i(p, at("uDetailed"), style.textures ? 1 : 0);
  glProgramUniform1i(p, at("uDetail"), 0);
  glProgramUniform1i(p, at("uNormalMap"), 1);
  const bool ids = image == VipmImage::kMaterialIds;
  glProgramUniform1i(p, at("uMaterialIds"), ids ? 1 : 0);
  if (!mColors.empty())
    glProgramUniform3fv(p, at("uMaterialColors"), GLsizei(mColors.size()), mColors[0].data());
  glProgramUniform2f(p, at("uBlotFade"), float(blots.fadeFrom), float(blots.blotFrom));
  glProgramUniform1i(p, at("uBlot"), 2);
  mProgram.use();
  glBindVertexArray(mVertexArray.id());
  glEnable(GL_DEPTH_TEST);
  glDisable(GL_CULL_FACE);  // as the static pass (terrain_pass.cpp): no pinholes

  // The whole chunk: depth and black; the flanges coloured.
  glDepthMask(GL_TRUE);
  glDepthFunc(GL_GREATER);
  glDisable(GL_BLEND);
  glProgramUniform1i(p, at("uPass"), 0);
  glProgramUniform1i(p, at("uMaterial"), -1);
  for (const Draw& d : draws) {
    setChunk(tree, d);
    const VipmGpuChunk::Range whole = d.chunk->parts().front();
    glProgramUniform1i(p, at("uFlange"), 0);
    // A blot: the whole chunk in one pass, coloured by its blot texture.
    glProgramUniform1i(p, at("uPass"), d.blot ? 3 : 0);
    stats.drawCalls += drawRange(*d.chunk, whole);
    stats.triangles += whole.count / 3 - d.chunk->replacedTriangles();  // those are empty
    stats.vertices += d.chunk->activeVertices();
    if (style.skirts && style.stitch == VipmStitch::kFlanges) {
      glProgramUniform1i(p, at("uFlange"), 1);
      glProgramUniform1i(p, at("uPass"), 0);
      stats.drawCalls += drawRange(*d.chunk, d.chunk->flanges());
      stats.triangles += d.chunk->flanges().count / 3;
    }
  }

  // Each material over its part, added where the depth is the whole pass's.
  glDepthMask(GL_FALSE);
  glDepthFunc(GL_EQUAL);
  glEnable(GL_BLEND);
  glBlendFunc(GL_ONE, GL_ONE);
  if (ids) glBlendEquation(GL_MAX);  // the largest weight's code wins
  glProgramUniform1i(p, at("uPass"), 1);
  glProgramUniform1i(p, at("uFlange"), 0);
  for (size_t m = 0; m < mDetails.size(); ++m) {
    glProgramUniform1i(p, at("uMaterial"), int(m));
    glBindTextureUnit(0, mDetails[m].id());
    for (const Draw& d : draws)
      for (const VipmGpuChunk::Range& r : d.chunk->parts())
        if (!d.blot && r.material == int(m) && r.count > 0) {
          setChunk(tree, d);
          stats.drawCalls += drawRange(*d.chunk, r);
        }
  }
  glBlendEquation(GL_FUNC_ADD);
  glDisable(GL_BLEND);
  glDepthMask(GL_TRUE);

  if (style.wireframe && !ids) {
    glProgramUniform1i(p, at("uPass"), 2);
    glPolygonMode(GL_FRONT_AND_BACK, GL_LINE);
    glEnable(GL_POLYGON_OFFSET_LINE);
    glPolygonOffset(1.0f, 1.0f);
    glDepthFunc(GL_GEQUAL);
    for (const Draw& d : draws) {
      setChunk(tree, d);
      stats.drawCalls += drawRange(*d.chunk, d.chunk->parts().front());
    }
    glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
    glDisable(GL_POLYGON_OFFSET_LINE);
  }
  glDepthFunc(GL_GREATER);
}

}  // namespace terralod
