#include "terralod/render/terrain_renderer.h"

#include <epoxy/gl.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <numbers>
#include <tuple>

#include "terrain_shaders.h"
#include "terralod/render/texture_placement.h"

namespace terralod {
namespace {

constexpr double kNearPlane = kNearPlaneMetres;  // reversed depth keeps precision far away

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

// World to camera rotation (the eye is the origin of the positions the shader sees).
glm::dmat4 viewRotation(const View& v) {
  return glm::lookAt(glm::dvec3(0.0), v.forward, v.up);
}

template <typename T>
void uploadGrowing(uint32_t& buffer, uint64_t& capacity, const std::vector<T>& data) {
  const uint64_t bytes = data.size() * sizeof(T);
  if (bytes > capacity) {
    if (buffer) glDeleteBuffers(1, &buffer);
    capacity = std::max<uint64_t>(bytes * 2, 4096);
    glCreateBuffers(1, &buffer);
    glNamedBufferStorage(buffer, GLsizeiptr(capacity), nullptr, GL_DYNAMIC_STORAGE_BIT);
  }
  if (bytes) glNamedBufferSubData(buffer, 0, GLsizeiptr(bytes), data.data());
}

// How far skirt bottoms move outwards (metres): an eighth of the part's shallowest skirt
// depth, so that the slant stays under any neighbour whose surface falls less steeply than
// 8:1 near the border, and at most an eighth of a grid cell.
float skirtSlant(const GpuChunkPart& p, const GpuChunk& chunk,
                 const std::array<double, 2>& spacing) {
  const double depth = double(p.skirtDepthSteps) * chunk.zStep;
  return float(std::min(depth / 8.0, std::min(spacing[0], spacing[1]) / 8.0));
}

}  // namespace

Result<TerrainRenderer> TerrainRenderer::create() {
  std::vector<ShaderProgram> terrain;
  for (int piecewise = 0; piecewise < 4; ++piecewise) {
    auto program = ShaderProgram::create(
        "terrain", {shaders::kTerrainVertex, shaders::terrainFragment(piecewise), {}});
    if (!program) return program.error();
    terrain.push_back(std::move(program).value());
  }
  auto sky = ShaderProgram::create("sky", {shaders::kSkyVertex, shaders::kSkyFragment, {}});
  if (!sky) return sky.error();
  auto boxes = ShaderProgram::create(
      "boxes", {shaders::kBoxVertex, shaders::withLevelPalette(shaders::kBoxFragment), {}});
  if (!boxes) return boxes.error();
  return TerrainRenderer(std::move(terrain), std::move(sky).value(), std::move(boxes).value());
}

TerrainRenderer::TerrainRenderer(std::vector<ShaderProgram> terrain, ShaderProgram sky,
                                 ShaderProgram boxes)
    : mTerrain(std::move(terrain)), mSky(std::move(sky)), mBoxes(std::move(boxes)) {
  // Box lines: float x, y, z relative to the eye, then the level.
  glCreateVertexArrays(1, &mBoxArray);
  glVertexArrayAttribFormat(mBoxArray, 0, 3, GL_FLOAT, GL_FALSE, 0);
  glVertexArrayAttribFormat(mBoxArray, 1, 1, GL_FLOAT, GL_FALSE, 3 * sizeof(float));
  glVertexArrayAttribBinding(mBoxArray, 0, 0);
  glVertexArrayAttribBinding(mBoxArray, 1, 0);
  glEnableVertexArrayAttrib(mBoxArray, 0);
  glEnableVertexArrayAttrib(mBoxArray, 1);
  glCreateVertexArrays(1, &mVertexArray);
  // 8-byte vertices: three 16-bit unsigned (x, y, z) and a signed 16-bit morph delta.
  glVertexArrayAttribIFormat(mVertexArray, 0, 3, GL_UNSIGNED_SHORT, 0);
  glVertexArrayAttribIFormat(mVertexArray, 1, 1, GL_SHORT, 6);
  glVertexArrayAttribBinding(mVertexArray, 0, 0);
  glVertexArrayAttribBinding(mVertexArray, 1, 0);
  glEnableVertexArrayAttrib(mVertexArray, 0);
  glEnableVertexArrayAttrib(mVertexArray, 1);
  // No placements until the tileset gives its sizes: GL's own sampling everywhere.
  const uint32_t none[4] = {};
  glCreateBuffers(1, &mPlacementBuffer);
  glNamedBufferStorage(mPlacementBuffer, sizeof none, none, 0);
}

void TerrainRenderer::setTextureSizes(std::span<const uint32_t> colorSizes,
                                      std::span<const uint32_t> normalSizes) {
  const std::vector<uint32_t> table = packPlacements(colorSizes, normalSizes);
  if (table.empty()) return;
  glDeleteBuffers(1, &mPlacementBuffer);
  glCreateBuffers(1, &mPlacementBuffer);
  glNamedBufferStorage(mPlacementBuffer, GLsizeiptr(table.size() * sizeof(uint32_t)), table.data(),
                       0);
  const size_t levels = table.size() / (2 * kPlacementEntries);
  mPiecewise.assign(levels, 0);
  for (size_t level = 0; level < levels; ++level)
    for (uint32_t kind = 0; kind < 2; ++kind)
      if (table[(level * 2 + kind) * kPlacementEntries] & 0x80000000u)
        mPiecewise[level] |= uint8_t(1u << kind);
}

TerrainRenderer::TerrainRenderer(TerrainRenderer&& o) noexcept
    : mTerrain(std::move(o.mTerrain)),
      mSky(std::move(o.mSky)),
      mBoxes(std::move(o.mBoxes)),
      mBoxArray(std::exchange(o.mBoxArray, 0)),
      mBoxBuffer(std::exchange(o.mBoxBuffer, 0)),
      mBoxBufferBytes(o.mBoxBufferBytes),
      mVertexArray(std::exchange(o.mVertexArray, 0)),
      mDrawBuffer(std::exchange(o.mDrawBuffer, 0)),
      mIndirectBuffer(std::exchange(o.mIndirectBuffer, 0)),
      mPlacementBuffer(std::exchange(o.mPlacementBuffer, 0)),
      mPiecewise(std::move(o.mPiecewise)),
      mDrawBufferBytes(o.mDrawBufferBytes),
      mIndirectBufferBytes(o.mIndirectBufferBytes),
      mBoundVertexBuffer(o.mBoundVertexBuffer) {}

TerrainRenderer::~TerrainRenderer() {
  if (mVertexArray) glDeleteVertexArrays(1, &mVertexArray);
  if (mDrawBuffer) glDeleteBuffers(1, &mDrawBuffer);
  if (mIndirectBuffer) glDeleteBuffers(1, &mIndirectBuffer);
  if (mPlacementBuffer) glDeleteBuffers(1, &mPlacementBuffer);
  if (mBoxArray) glDeleteVertexArrays(1, &mBoxArray);
  if (mBoxBuffer) glDeleteBuffers(1, &mBoxBuffer);
}

void TerrainRenderer::drawBoxes(const View& view, const ChunkTree& tree,
                                std::span<const SelectedChunk> selection,
                                const GpuChunkStore& store, const glm::mat4& viewProjection) {
  mBoxLines.clear();
  const glm::dvec3 eye = view.camera.eye;
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
          mBoxLines.insert(mBoxLines.end(), {p.x, p.y, p.z, float(n.level)});
      }
  }
  if (mBoxLines.empty()) return;
  uploadGrowing(mBoxBuffer, mBoxBufferBytes, mBoxLines);
  glVertexArrayVertexBuffer(mBoxArray, 0, mBoxBuffer, 0, 4 * sizeof(float));
  glBindVertexArray(mBoxArray);
  mBoxes.use();
  glProgramUniformMatrix4fv(mBoxes.id(), mBoxes.uniformLocation("uViewProjection"), 1, GL_FALSE,
                            glm::value_ptr(viewProjection));
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_GEQUAL);
  glDrawArrays(GL_LINES, 0, GLsizei(mBoxLines.size() / 4));
}

DrawStats TerrainRenderer::draw(const View& view, const ChunkTree& tree,
                                std::span<const SelectedChunk> selection,
                                const GpuChunkStore& store, const TerrainStyle& style) {
  DrawStats stats;
  const glm::dvec3 eye = view.camera.eye;
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
    const bool textured = chunk->textured && style.textures;
    const uint64_t group =
        textured ? (uint64_t(chunk->color.array) << 32) | chunk->normal.array : ~uint64_t{0};
    const uint32_t piecewise =
        textured && n.level < mPiecewise.size() ? mPiecewise[size_t(n.level)] : 0u;
    for (const GpuChunkPart& p : chunk->parts) {
      const uint32_t count = style.skirts ? p.indexCount : p.surfaceIndexCount;
      if (count == 0) continue;
      PendingDraw d;
      d.group = group;
      d.piecewise = piecewise;
      d.colorSize = chunk->color.size;
      d.normalSize = chunk->normal.size;
      d.draw = {float(n.box.min[0] - eye.x),
                float(n.box.min[1] - eye.y),
                float(chunk->zBase - eye.z),
                s.morph,
                float(spacing[0]),
                float(spacing[1]),
                float(chunk->zStep),
                float(n.level),
                std::bit_cast<float>(p.surfaceIndexCount / 3),
                std::bit_cast<float>(chunk->color.layer),
                std::bit_cast<float>(chunk->normal.layer),
                std::bit_cast<float>(cells),
                std::bit_cast<float>(p.firstSkirtVertex),
                std::bit_cast<float>(skirtSlant(p, *chunk, spacing)),
                0.0f,
                0.0f};
      // DrawElementsIndirectCommand: count, instanceCount, firstIndex, baseVertex, baseInstance.
      d.command = {count, 1u, p.firstIndex, p.baseVertex, 0u};
      mPending.push_back(d);
      stats.triangles += count / 3;
    }
  }
  std::stable_sort(mPending.begin(), mPending.end(),
                   [](const PendingDraw& a, const PendingDraw& b) {
                     return std::tie(a.group, a.piecewise) < std::tie(b.group, b.piecewise);
                   });
  mDraws.clear();
  mCommands.clear();
  for (const PendingDraw& d : mPending) {
    mDraws.insert(mDraws.end(), d.draw.begin(), d.draw.end());
    mCommands.insert(mCommands.end(), d.command.begin(), d.command.end());
  }
  stats.drawCommands = uint32_t(mCommands.size() / 5);

  const glm::dmat4 projection = reversedInfinitePerspective(view);
  const glm::mat4 viewProjection(projection * viewRotation(view));
  const glm::vec3 background{style.background[0] / 255.0f, style.background[1] / 255.0f,
                             style.background[2] / 255.0f};
  // Haze: the background lightened towards white, as distant air looks.
  const glm::vec3 haze = glm::mix(background, glm::vec3(0.92f, 0.93f, 0.95f), 0.55f);

  glViewport(0, 0, view.camera.width, view.camera.height);
  glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE);
  glClearColor(background.r, background.g, background.b, 1.0f);
  glClearDepth(0.0);
  glDepthMask(GL_TRUE);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  glBindVertexArray(mVertexArray);

  if (style.sky) {
    glDisable(GL_DEPTH_TEST);
    mSky.use();
    const glm::mat4 inverse(glm::inverse(projection * viewRotation(view)));
    glUniformMatrix4fv(mSky.uniformLocation("uInverseViewProjection"), 1, GL_FALSE,
                       glm::value_ptr(inverse));
    glUniform3fv(mSky.uniformLocation("uBackground"), 1, glm::value_ptr(background));
    glUniform3fv(mSky.uniformLocation("uHaze"), 1, glm::value_ptr(haze));
    glDrawArrays(GL_TRIANGLES, 0, 3);
    ++stats.drawCalls;
  }
  if (mCommands.empty()) return stats;

  uploadGrowing(mDrawBuffer, mDrawBufferBytes, mDraws);
  uploadGrowing(mIndirectBuffer, mIndirectBufferBytes, mCommands);
  glVertexArrayVertexBuffer(mVertexArray, 0, store.vertexBuffer(), 0, sizeof(ChunkVertex));
  glVertexArrayElementBuffer(mVertexArray, store.indexBuffer());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, mDrawBuffer);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, mPlacementBuffer);
  glBindBuffer(GL_DRAW_INDIRECT_BUFFER, mIndirectBuffer);

  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_GREATER);
  // No back-face culling. Seen from above, a height field's back faces all lie behind front
  // faces, so culling would only save work, but it can open pinholes: where a steep slope
  // folds over in the image, a back-facing sliver a ten-thousandth of a pixel across can be
  // the triangle that covers a pixel centre once the rasteriser has snapped the vertices to
  // its subpixel grid, and a pipeline that decides facing before snapping (Mesa's, in floating
  // point) drops it. Drawing both faces leaves no pixel uncovered (docs/architecture.md).
  glDisable(GL_CULL_FACE);
  const double azimuth = style.sunAzimuthDegrees * std::numbers::pi / 180.0;
  const double elevation = style.sunElevationDegrees * std::numbers::pi / 180.0;
  const glm::vec3 sun(std::sin(azimuth) * std::cos(elevation),
                      std::cos(azimuth) * std::cos(elevation), std::sin(elevation));
  const Box& extent = tree.extent();
  const double diagonal = std::hypot(extent.max[0] - extent.min[0], extent.max[1] - extent.min[1]);
  const glm::vec3 hazeLinear = glm::pow(haze, glm::vec3(2.2f));
  // The frame's uniforms, in each program variant this frame uses.
  uint32_t variantsUsed = 0;
  for (const PendingDraw& d : mPending) variantsUsed |= 1u << d.piecewise;
  for (uint32_t v = 0; v < mTerrain.size(); ++v) {
    if (!(variantsUsed & (1u << v))) continue;
    const ShaderProgram& terrain = mTerrain[v];
    const GLuint program = terrain.id();
    glProgramUniformMatrix4fv(program, terrain.uniformLocation("uViewProjection"), 1, GL_FALSE,
                              glm::value_ptr(viewProjection));
    glProgramUniform1f(program, terrain.uniformLocation("uEyeHeight"), float(eye.z));
    glProgramUniform1i(program, terrain.uniformLocation("uColorBy"), int(style.colorBy));
    glProgramUniform3fv(program, terrain.uniformLocation("uSun"), 1, glm::value_ptr(sun));
    glProgramUniform2f(program, terrain.uniformLocation("uHeightRange"), float(extent.min[2]),
                       float(extent.max[2]));
    glProgramUniform3fv(program, terrain.uniformLocation("uHaze"), 1, glm::value_ptr(hazeLinear));
    glProgramUniform1f(program, terrain.uniformLocation("uHazeDistance"),
                       float(std::max(diagonal, 1.0) * 1.5));
    glProgramUniform1i(program, terrain.uniformLocation("uColor"), 0);
    glProgramUniform1i(program, terrain.uniformLocation("uNormal"), 1);
  }
  auto drawGroups = [&](int wireframe) {
    for (size_t first = 0; first < mPending.size();) {
      size_t last = first;
      while (last < mPending.size() && mPending[last].group == mPending[first].group &&
             mPending[last].piecewise == mPending[first].piecewise)
        ++last;
      const PendingDraw& d = mPending[first];
      const ShaderProgram& terrain = mTerrain[d.piecewise];
      const GLuint program = terrain.id();
      terrain.use();
      glProgramUniform1i(program, terrain.uniformLocation("uWire"), wireframe);
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
      ++stats.drawCalls;
      first = last;
    }
  };
  drawGroups(0);
  if (style.wireframe) {
    // Edges on top of the surface: drawn again as lines, pulled towards the eye a little.
    glPolygonMode(GL_FRONT_AND_BACK, GL_LINE);
    glEnable(GL_POLYGON_OFFSET_LINE);
    glPolygonOffset(1.0f, 1.0f);
    glDepthFunc(GL_GEQUAL);
    drawGroups(1);
    glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
    glDisable(GL_POLYGON_OFFSET_LINE);
  }
  if (style.chunkBoxes) {
    drawBoxes(view, tree, selection, store, viewProjection);
    ++stats.drawCalls;
  }
  glDisable(GL_DEPTH_TEST);
  glBindVertexArray(0);
  return stats;
}

}  // namespace terralod
