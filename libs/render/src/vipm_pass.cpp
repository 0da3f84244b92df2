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
  // Its chunk's slot in its block (one byte).
  glVertexArrayAttribIFormat(vao, 4, 1, GL_UNSIGNED_BYTE, 0);
  for (GLuint a = 0; a < 5; ++a) {
    glVertexArrayAttribBinding(vao, a, a < 3 ? a : a - 1);
    glEnableVertexArrayAttrib(vao, a);
  }
}

void VipmPass::bindBlock(const VipmBlock& block, uint32_t firstVertex) const {
  const GLuint vao = mVertexArray.id();
  glVertexArrayVertexBuffer(vao, 0, block.positionBuffer(), GLintptr(firstVertex) * 12, 12);
  glVertexArrayVertexBuffer(vao, 1, block.materialBuffer(), GLintptr(firstVertex), 1);
  glVertexArrayVertexBuffer(vao, 2, block.weightBuffer(), GLintptr(firstVertex) * 8, 8);
  glVertexArrayVertexBuffer(vao, 3, block.slotBuffer(), GLintptr(firstVertex), 1);
  glBindTextureUnit(1, block.normalArray());
  glBindTextureUnit(2, block.blotArray());  // blots, and the fade toward them
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
  glProgramUniform1f(p, mProgram.uniformLocation("uTexelCells"), float(c.texelCells()));
  // World-space detail coordinates, reduced to one period in double at the chunk's corner.
  std::array<float, 2> origin{};
  for (int k = 0; k < 2; ++k) {
    const double period = kDetailCells * spacing[size_t(k)];
    const double u = n.box.min[size_t(k)] / period;
    origin[size_t(k)] = float(u - std::floor(u));
  }
  glProgramUniform2f(p, mProgram.uniformLocation("uDetailOrigin"), origin[0], origin[1]);
  glProgramUniform1f(p, mProgram.uniformLocation("uLevel"), float(n.level));
  // Colour by kind: a leaf, a root or above, a blot.
  const bool leaf = int(n.level) + 1 == tree.levelCount();
  glProgramUniform1i(p, mProgram.uniformLocation("uKind"), d.blot ? 2 : leaf ? 0 : 1);
  glProgramUniform1f(p, mProgram.uniformLocation("uMorph"), d.morph);
  glProgramUniform1i(p, mProgram.uniformLocation("uBlock"), 0);
  bindBlock(c.block(), c.vertices().first);
  glVertexArrayElementBuffer(mVertexArray.id(), c.indexBuffer());
}

void VipmPass::drawBlock(const ChunkTree& tree, std::span<const Draw* const> members, bool flanges,
                         DrawStats& stats) const {
  const GLuint p = mProgram.id();
  VipmBlock& block = members.front()->chunk->block();
  VipmBlock::Batch& batch = block.batch();
  // The index list again only when one of its chunks or what they draw changed.
  mKey.clear();
  for (const Draw* d : members) {
    mKey.push_back(d->chunk->serial());
    mKey.push_back(d->chunk->indexVersion());
    mKey.push_back(d->chunk->applied());
  }
  mKey.push_back(flanges);
  if (mKey != batch.key) {
    batch.key = mKey;
    batch.indices.clear();
    mFlangeIndices.clear();
    for (const Draw* d : members)
      d->chunk->appendDrawn(batch.indices, flanges ? &mFlangeIndices : nullptr);
    batch.surfaceIndices = uint32_t(batch.indices.size());
    batch.indices.insert(batch.indices.end(), mFlangeIndices.begin(), mFlangeIndices.end());
    if (batch.indices.size() > batch.capacity) {
      batch.capacity = uint32_t(batch.indices.size() * 5 / 4 + 64);
      batch.buffer = GlBuffer::make();
      glNamedBufferStorage(batch.buffer.id(), GLsizeiptr(batch.capacity) * 4, nullptr,
                           GL_DYNAMIC_STORAGE_BIT);
    }
    glNamedBufferSubData(batch.buffer.id(), 0, GLsizeiptr(batch.indices.size() * 4),
                         batch.indices.data());
  }
  std::array<float, 2 * VipmBlock::kSlots> corners{};
  std::array<float, VipmBlock::kSlots> zBases{}, morphs{};
  for (const Draw* d : members) {
    const VipmGpuChunk& c = *d->chunk;
    const auto s = size_t(c.slot());
    corners[2 * s] = float(c.cornerX() - mAnchor[0]);
    corners[2 * s + 1] = float(c.cornerY() - mAnchor[1]);
    zBases[s] = float(c.zBase());
    morphs[s] = d->morph;
    stats.vertices += c.activeVertices();
  }
  auto at = [&](const char* name) { return mProgram.uniformLocation(name); };
  glProgramUniform1i(p, at("uBlock"), 1);
  glProgramUniform2fv(p, at("uSlotCorner"), VipmBlock::kSlots, corners.data());
  glProgramUniform1fv(p, at("uSlotZBase"), VipmBlock::kSlots, zBases.data());
  glProgramUniform1fv(p, at("uSlotMorph"), VipmBlock::kSlots, morphs.data());
  glProgramUniform1i(p, at("uFlangeFrom"), GLint(batch.surfaceIndices / 3));
  const auto gridSize = float(members.front()->chunk->normalSize());
  glProgramUniform2f(p, at("uGridSize"), gridSize, gridSize);
  glProgramUniform1f(p, at("uTexelCells"), float(members.front()->chunk->texelCells()));
  glProgramUniform1f(p, at("uLevel"), float(tree.node(members.front()->node).level));
  glProgramUniform1i(p, at("uKind"), 3);
  glProgramUniform1i(p, at("uPass"), 3);
  glProgramUniform1i(p, at("uFlange"), 0);
  bindBlock(block, 0);
  glVertexArrayElementBuffer(mVertexArray.id(), batch.buffer.id());
  if (!batch.indices.empty())
    glDrawElements(GL_TRIANGLES, GLsizei(batch.indices.size()), GL_UNSIGNED_INT, nullptr);
  stats.drawCalls += 1;
  stats.triangles += batch.indices.size() / 3;
  stats.superChunks += 1;
  stats.superChunkBlots += uint32_t(members.size());
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
  glProgramUniform1i(p, at("uUnlit"), style.shading == Shading::kUnlit ? 1 : 0);
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
  // Blots that share a block with another blot: one call for the block's.
  const bool flanges = style.skirts && style.stitch == VipmStitch::kFlanges;
  mBlockDraws.clear();
  if (style.superChunks == VipmSuperChunks::kOn && !ids)
    for (const Draw& d : draws)
      if (d.blot) mBlockDraws.push_back(&d);
  std::sort(mBlockDraws.begin(), mBlockDraws.end(), [](const Draw* a, const Draw* b) {
    const VipmBlock* x = &a->chunk->block();
    const VipmBlock* y = &b->chunk->block();
    return x != y ? std::less<>()(x, y) : a->chunk->slot() < b->chunk->slot();
  });
  mInBlock.assign(draws.size(), 0);
  for (size_t i = 0; i < mBlockDraws.size();) {
    size_t j = i + 1;
    while (j < mBlockDraws.size() &&
           &mBlockDraws[j]->chunk->block() == &mBlockDraws[i]->chunk->block())
      ++j;
    if (j - i >= 2) {
      drawBlock(tree, std::span(mBlockDraws).subspan(i, j - i), flanges, stats);
      for (size_t k = i; k < j; ++k) mInBlock[size_t(mBlockDraws[k] - draws.data())] = 1;
    }
    i = j;
  }
  for (const Draw& d : draws) {
    if (mInBlock[size_t(&d - draws.data())]) continue;
    setChunk(tree, d);
    const VipmGpuChunk::Range whole = d.chunk->parts().front();
    glProgramUniform1i(p, at("uFlange"), 0);
    // A blot: the whole chunk in one pass, coloured by its blot texture.
    glProgramUniform1i(p, at("uPass"), d.blot ? 3 : 0);
    stats.drawCalls += drawRange(*d.chunk, whole);
    stats.triangles += whole.count / 3 - d.chunk->replacedTriangles();  // those are empty
    stats.vertices += d.chunk->activeVertices();
    if (flanges) {
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
