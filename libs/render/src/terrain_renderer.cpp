#include "terralod/render/terrain_renderer.h"

#include <epoxy/gl.h>

#include <algorithm>
#include <vector>

#include "chunk_box_pass.h"
#include "frame_colors.h"
#include "sky_pass.h"
#include "terrain_pass.h"

namespace terralod {

struct TerrainRenderer::Passes {
  SkyPass sky;
  TerrainPass terrain;
  ChunkBoxPass boxes;
  std::vector<std::unique_ptr<CompositedLayer>> layers;
};

namespace {

// Viewport, clip control and a cleared target: the background colour, depth 0 (infinitely far
// in reversed-Z).
void clearFrame(const FrameContext& frame) {
  const Viewport& v = frame.viewport;
  glViewport(v.x, v.y, v.width, v.height);
  glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE);
  const glm::vec3 background = backgroundColor(frame.style);
  glClearColor(background.r, background.g, background.b, 1.0f);
  glClearDepth(0.0);
  glDepthMask(GL_TRUE);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
}

// The layers over the opaque terrain, in the state composited_layer.h promises them.
uint32_t drawLayers(const FrameContext& frame,
                    const std::vector<std::unique_ptr<CompositedLayer>>& layers) {
  if (layers.empty()) return 0;
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_GEQUAL);
  glDepthMask(GL_FALSE);
  glDisable(GL_BLEND);
  glDisable(GL_CULL_FACE);
  // The terrain's depth writes are done before any layer samples the depth texture.
  if (frame.depth.readable()) glTextureBarrier();
  uint32_t calls = 0;
  for (const auto& layer : layers) calls += layer->draw(frame);
  glDepthMask(GL_TRUE);
  return calls;
}

}  // namespace

Result<TerrainRenderer> TerrainRenderer::create() {
  auto sky = SkyPass::create();
  if (!sky) return sky.error();
  auto terrain = TerrainPass::create();
  if (!terrain) return terrain.error();
  auto boxes = ChunkBoxPass::create();
  if (!boxes) return boxes.error();
  return TerrainRenderer(std::make_unique<Passes>(
      Passes{std::move(sky).value(), std::move(terrain).value(), std::move(boxes).value(), {}}));
}

TerrainRenderer::TerrainRenderer(std::unique_ptr<Passes> passes) : mPasses(std::move(passes)) {}
TerrainRenderer::TerrainRenderer(TerrainRenderer&& other) noexcept = default;
TerrainRenderer::~TerrainRenderer() = default;

void TerrainRenderer::setSnowLine(std::span<const float> samples, uint32_t lastRow,
                                  double spacingY) {
  mPasses->terrain.setSnowLine(samples, lastRow, spacingY);
}

void TerrainRenderer::setTextureSizes(std::span<const uint32_t> colorSizes,
                                      std::span<const uint32_t> normalSizes) {
  mPasses->terrain.setTextureSizes(colorSizes, normalSizes);
}

CompositedLayer& TerrainRenderer::addLayer(std::unique_ptr<CompositedLayer> layer) {
  mPasses->layers.push_back(std::move(layer));
  return *mPasses->layers.back();
}

FrameContext TerrainRenderer::beginFrame(const View& view, const TerrainStyle& style,
                                         const ChunkTree& tree, DrawStats& stats) {
  FrameContext frame = makeFrameContext(view, style, boundDepthTexture());
  clearFrame(frame);
  if (style.sky) stats.drawCalls += mPasses->sky.draw(frame, std::min(0.0, tree.extent().min[2]));
  return frame;
}

void TerrainRenderer::drawStaticChunks(const FrameContext& frame, const ChunkTree& tree,
                                       std::span<const SelectedChunk> chunks,
                                       const GpuChunkStore& store, DrawStats& stats) {
  TerrainPass& terrain = mPasses->terrain;
  const DrawStats prepared = terrain.prepare(frame, tree, chunks, store);
  stats.chunks += prepared.chunks;
  stats.missing += prepared.missing;
  stats.drawCommands += prepared.drawCommands;
  stats.triangles += prepared.triangles;
  stats.vertices += prepared.vertices;
  stats.drawCalls += prepared.drawCalls;
  if (terrain.empty()) return;
  stats.drawCalls += terrain.draw(frame, tree, store, TerrainDrawMode::kSurface);
  if (frame.style.wireframe)
    stats.drawCalls += terrain.draw(frame, tree, store, TerrainDrawMode::kWireframe);
}

void TerrainRenderer::finishFrame(const FrameContext& frame, const ChunkTree& tree,
                                  std::span<const SelectedChunk> selection,
                                  const GpuChunkStore& store, DrawStats& stats) {
  stats.drawCalls += drawLayers(frame, mPasses->layers);
  if (frame.style.chunkBoxes && !selection.empty())
    stats.drawCalls += mPasses->boxes.draw(frame, tree, selection, store);
  glDisable(GL_DEPTH_TEST);
  glBindVertexArray(0);
}

DrawStats TerrainRenderer::draw(const View& view, const ChunkTree& tree,
                                std::span<const SelectedChunk> selection,
                                const GpuChunkStore& store, const TerrainStyle& style) {
  DrawStats stats;
  const FrameContext frame = beginFrame(view, style, tree, stats);
  drawStaticChunks(frame, tree, selection, store, stats);
  finishFrame(frame, tree, selection, store, stats);
  return stats;
}

}  // namespace terralod
