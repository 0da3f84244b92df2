#include "terrain_pass.h"

#include <epoxy/gl.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <glm/gtc/type_ptr.hpp>
#include <numbers>
#include <tuple>

#include "atmosphere.h"
#include "frame_colors.h"
#include "terrain_shaders.h"
#include "terralod/render/texture_placement.h"

namespace terralod {
namespace {

// How far skirt bottoms move outwards (metres): an eighth of the part's shallowest skirt
// depth, so that the slant stays under any neighbour whose surface falls less steeply than
// 8:1 near the border, and at most an eighth of a grid cell.
float skirtSlant(const GpuChunkPart& p, const GpuChunk& chunk,
                 const std::array<double, 2>& spacing) {
  const double depth = double(p.skirtDepthSteps) * chunk.zStep;
  return float(std::min(depth / 8.0, std::min(spacing[0], spacing[1]) / 8.0));
}

}  // namespace

Result<TerrainPass> TerrainPass::create() {
  std::vector<ShaderProgram> programs;
  for (int variant = 0; variant < 8; ++variant) {
    auto program = ShaderProgram::create(
        "terrain", {shaders::kTerrainVertex, shaders::terrainFragment(variant), {}});
    if (!program) return program.error();
    programs.push_back(std::move(program).value());
  }
  return TerrainPass(std::move(programs));
}

TerrainPass::TerrainPass(std::vector<ShaderProgram> programs)
    : mPrograms(std::move(programs)),
      mVertexArray(GlVertexArray::make()),
      mPlacementBuffer(GlBuffer::make()),
      mSnowLine(kSnowLineSamples, float(snowLine(kUnknownLatitude))) {
  // 8-byte vertices: three 16-bit unsigned (x, y, z) and a signed 16-bit morph delta.
  const GLuint vao = mVertexArray.id();
  glVertexArrayAttribIFormat(vao, 0, 3, GL_UNSIGNED_SHORT, 0);
  glVertexArrayAttribIFormat(vao, 1, 1, GL_SHORT, 6);
  glVertexArrayAttribBinding(vao, 0, 0);
  glVertexArrayAttribBinding(vao, 1, 0);
  glEnableVertexArrayAttrib(vao, 0);
  glEnableVertexArrayAttrib(vao, 1);
  // No placements until the tileset gives its sizes: GL's own sampling everywhere.
  const uint32_t none[4] = {};
  glNamedBufferStorage(mPlacementBuffer.id(), sizeof none, none, 0);
}

void TerrainPass::setTextureSizes(std::span<const uint32_t> colorSizes,
                                  std::span<const uint32_t> normalSizes) {
  const std::vector<uint32_t> table = packPlacements(colorSizes, normalSizes);
  if (table.empty()) return;
  mPlacementBuffer = GlBuffer::make();
  glNamedBufferStorage(mPlacementBuffer.id(), GLsizeiptr(table.size() * sizeof(uint32_t)),
                       table.data(), 0);
  const size_t levels = table.size() / (2 * kPlacementEntries);
  mPiecewise.assign(levels, 0);
  for (size_t level = 0; level < levels; ++level)
    for (uint32_t kind = 0; kind < 2; ++kind)
      if (table[(level * 2 + kind) * kPlacementEntries] & 0x80000000u)
        mPiecewise[level] |= uint8_t(1u << kind);
}

void TerrainPass::setSnowLine(std::span<const float> samples, uint32_t lastRow, double spacingY) {
  for (size_t k = 0; k < mSnowLine.size(); ++k)
    mSnowLine[k] = snowLineAt(samples, double(k) / double(mSnowLine.size() - 1));
  mSnowFraction = float(1.0 / (std::max(1.0, double(lastRow)) * spacingY));
}

DrawStats TerrainPass::prepare(const FrameContext& frame, const ChunkTree& tree,
                               std::span<const SelectedChunk> selection,
                               const GpuChunkStore& store) {
  DrawStats stats;
  const glm::dvec3 eye = frame.eye;
  const auto spacing = tree.spacing();
  // Draws are grouped by the texture arrays they sample: one multi-draw per group.
  mPending.clear();
  for (const SelectedChunk& s : selection) {
    const GpuChunk* chunk = store.find(s.node);
    if (!chunk) {
      ++stats.missing;
      continue;
    }
    ++stats.chunks;
    const ChunkNode& n = tree.node(s.node);
    const uint32_t cells = uint32_t(tree.chunkCells(n.level));
    const DrawnTexture owner = drawnTexture(tree, store, s.node);
    const bool textured = owner.chunk && frame.style.textures;
    const GpuChunk& tex = textured ? *owner.chunk : *chunk;
    const uint64_t group =
        textured ? (uint64_t(tex.color.array) << 32) | tex.normal.array : ~uint64_t{0};
    const uint32_t variant =
        textured ? (owner.level < mPiecewise.size() ? mPiecewise[owner.level] : 0u) |
                       (tex.shaded ? 4u : 0u)
                 : 0u;
    for (const GpuChunkPart& p : chunk->parts) {
      const uint32_t count = frame.style.skirts ? p.indexCount : p.surfaceIndexCount;
      if (count == 0) continue;
      PendingDraw d;
      d.group = group;
      d.variant = variant;
      d.colorSize = tex.color.size;
      d.normalSize = tex.normal.size;
      d.draw = {float(n.box.min[0] - eye.x),
                float(n.box.min[1] - eye.y),
                float(chunk->zBase - eye.z),
                s.morph,
                float(spacing[0]),
                float(spacing[1]),
                float(chunk->zStep),
                float(n.level),
                std::bit_cast<float>(p.surfaceIndexCount / 3),
                std::bit_cast<float>(tex.color.layer),
                std::bit_cast<float>(tex.normal.layer),
                std::bit_cast<float>(cells),
                std::bit_cast<float>(p.firstSkirtVertex),
                std::bit_cast<float>(skirtSlant(p, *chunk, spacing)),
                std::bit_cast<float>(owner.depth | owner.level << 8),
                std::bit_cast<float>(owner.column | owner.row << 16)};
      // DrawElementsIndirectCommand: count, instanceCount, firstIndex, baseVertex, baseInstance.
      d.command = {count, 1u, p.firstIndex, p.baseVertex, 0u};
      mPending.push_back(d);
      stats.triangles += count / 3;
      stats.vertices += p.firstSkirtVertex;
    }
  }
  std::stable_sort(mPending.begin(), mPending.end(),
                   [](const PendingDraw& a, const PendingDraw& b) {
                     return std::tie(a.group, a.variant) < std::tie(b.group, b.variant);
                   });
  mDraws.clear();
  mCommands.clear();
  for (const PendingDraw& d : mPending) {
    mDraws.insert(mDraws.end(), d.draw.begin(), d.draw.end());
    mCommands.insert(mCommands.end(), d.command.begin(), d.command.end());
  }
  stats.drawCommands = uint32_t(mCommands.size() / 5);
  if (!mCommands.empty()) {
    mDrawBuffer.upload(mDraws);
    mIndirectBuffer.upload(mCommands);
  }
  return stats;
}

void TerrainPass::setFrameUniforms(const FrameContext& frame, const ChunkTree& tree) {
  const TerrainStyle& style = frame.style;
  const double azimuth = style.sunAzimuthDegrees * std::numbers::pi / 180.0;
  const double elevation = style.sunElevationDegrees * std::numbers::pi / 180.0;
  const glm::vec3 sun(std::sin(azimuth) * std::cos(elevation),
                      std::cos(azimuth) * std::cos(elevation), std::sin(elevation));
  const Box& extent = tree.extent();
  const glm::vec3 hazeLinear = glm::pow(hazeColor(style), glm::vec3(2.2f));
  // The frame's uniforms, in each program variant this frame uses.
  uint32_t variantsUsed = 0;
  for (const PendingDraw& d : mPending) variantsUsed |= 1u << d.variant;
  for (uint32_t v = 0; v < mPrograms.size(); ++v) {
    if (!(variantsUsed & (1u << v))) continue;
    const ShaderProgram& terrain = mPrograms[v];
    const GLuint program = terrain.id();
    glProgramUniformMatrix4fv(program, terrain.uniformLocation("uViewProjection"), 1, GL_FALSE,
                              glm::value_ptr(frame.viewProjection));
    glProgramUniform1f(program, terrain.uniformLocation("uEyeHeight"), float(frame.eye.z));
    if (v & 4u) {
      glProgramUniform1f(program, terrain.uniformLocation("uEyeNorth"), float(frame.eye.y));
      glProgramUniform1fv(program, terrain.uniformLocation("uSnowLine[0]"),
                          GLsizei(mSnowLine.size()), mSnowLine.data());
      glProgramUniform1f(program, terrain.uniformLocation("uSnowFraction"), mSnowFraction);
    }
    glProgramUniform1i(program, terrain.uniformLocation("uColorBy"), int(style.colorBy));
    glProgramUniform1i(program, terrain.uniformLocation("uUnlit"),
                       style.shading == Shading::kUnlit ? 1 : 0);
    glProgramUniform3fv(program, terrain.uniformLocation("uSun"), 1, glm::value_ptr(sun));
    glProgramUniform2f(program, terrain.uniformLocation("uHeightRange"), float(extent.min[2]),
                       float(extent.max[2]));
    glProgramUniform3fv(program, terrain.uniformLocation("uHaze"), 1, glm::value_ptr(hazeLinear));
    glProgramUniform1f(program, terrain.uniformLocation("uScaleHeight"), float(kScaleHeight));
    glProgramUniform1f(program, terrain.uniformLocation("uExtinction"), float(extinction(style)));
    glProgramUniform1i(program, terrain.uniformLocation("uColor"), 0);
    glProgramUniform1i(program, terrain.uniformLocation("uNormal"), 1);
  }
}

uint32_t TerrainPass::draw(const FrameContext& frame, const ChunkTree& tree,
                           const GpuChunkStore& store, TerrainDrawMode mode) {
  if (mCommands.empty()) return 0;
  glBindVertexArray(mVertexArray.id());
  glVertexArrayVertexBuffer(mVertexArray.id(), 0, store.vertexBuffer(), 0, sizeof(ChunkVertex));
  glVertexArrayElementBuffer(mVertexArray.id(), store.indexBuffer());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, mDrawBuffer.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, mPlacementBuffer.id());
  glBindBuffer(GL_DRAW_INDIRECT_BUFFER, mIndirectBuffer.id());
  glEnable(GL_DEPTH_TEST);
  // No back-face culling. Seen from above, a height field's back faces all lie behind front
  // faces, so culling would only save work, but it can open pinholes: where a steep slope
  // folds over in the image, a back-facing sliver a ten-thousandth of a pixel across can be
  // the triangle that covers a pixel centre once the rasteriser has snapped the vertices to
  // its subpixel grid, and a pipeline that decides facing before snapping (Mesa's, in floating
  // point) drops it. Drawing both faces leaves no pixel uncovered (docs/architecture.md).
  glDisable(GL_CULL_FACE);
  if (mode == TerrainDrawMode::kSurface) {
    glDepthMask(GL_TRUE);
    glDepthFunc(GL_GREATER);
    setFrameUniforms(frame, tree);
    return drawGroups(store, mode);
  }
  // Edges on top of the surface: drawn again as lines, pulled towards the eye a little.
  glPolygonMode(GL_FRONT_AND_BACK, GL_LINE);
  glEnable(GL_POLYGON_OFFSET_LINE);
  glPolygonOffset(1.0f, 1.0f);
  glDepthFunc(GL_GEQUAL);
  const uint32_t calls = drawGroups(store, mode);
  glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
  glDisable(GL_POLYGON_OFFSET_LINE);
  return calls;
}

uint32_t TerrainPass::drawGroups(const GpuChunkStore& store, TerrainDrawMode mode) {
  uint32_t calls = 0;
  for (size_t first = 0; first < mPending.size();) {
    size_t last = first;
    while (last < mPending.size() && mPending[last].group == mPending[first].group &&
           mPending[last].variant == mPending[first].variant)
      ++last;
    const PendingDraw& d = mPending[first];
    const ShaderProgram& terrain = mPrograms[d.variant];
    const GLuint program = terrain.id();
    terrain.use();
    glProgramUniform1i(program, terrain.uniformLocation("uWire"),
                       mode == TerrainDrawMode::kWireframe ? 1 : 0);
    const bool hasTexture = d.group != ~uint64_t{0};
    glProgramUniform1i(program, terrain.uniformLocation("uTextured"), hasTexture ? 1 : 0);
    if (hasTexture) {
      glBindTextureUnit(0, store.textures().arrayTexture(uint32_t(d.group >> 32)));
      glBindTextureUnit(1, store.textures().arrayTexture(uint32_t(d.group & 0xFFFFFFFFu)));
      glProgramUniform2f(program, terrain.uniformLocation("uTileSizes"), float(d.colorSize),
                         float(d.normalSize));
    }
    glProgramUniform1i(program, terrain.uniformLocation("uDrawBase"), GLint(first));
    glMultiDrawElementsIndirect(GL_TRIANGLES, GL_UNSIGNED_SHORT,
                                reinterpret_cast<const void*>(first * 5 * sizeof(uint32_t)),
                                GLsizei(last - first), 0);
    ++calls;
    first = last;
  }
  return calls;
}

}  // namespace terralod
