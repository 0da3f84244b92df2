#include "terralod/render/terrain_scene.h"

#include <epoxy/gl.h>

#include <algorithm>
#include <cmath>

namespace terralod {

Result<std::unique_ptr<TerrainScene>> TerrainScene::create(std::unique_ptr<TilesetReader> tileset,
                                                           SceneOptions options) {
  auto renderer = TerrainRenderer::create();
  if (!renderer) return renderer.error();
  // Each level's tile sizes (metadata "texture": "levels"): where the mips keep their texels.
  if (const auto& levels = tileset->metadata().textureLevels; !levels.empty()) {
    std::vector<uint32_t> colorSizes, normalSizes;
    for (const TextureLevelSizes& l : levels) {
      colorSizes.push_back(l.color);
      normalSizes.push_back(l.normal);
    }
    renderer->setTextureSizes(colorSizes, normalSizes);
  }
  const TilesetMetadata& metadata = tileset->metadata();
  renderer->setSnowLine(metadata.snowLine, metadata.snowLineLastRow, tileset->header().spacingY);
  ChunkTree tree(tileset->header(), tileset->nodes());
  std::unique_ptr<TerrainScene> scene(new TerrainScene(
      std::move(tileset), std::move(tree), std::move(renderer).value(), std::move(options)));
  if (scene->mOptions.context) {
    // GPU memory made ahead on a worker; where a driver cannot share contexts, made when needed.
    auto shared = scene->mOptions.context->createShared();
    auto worker = shared ? GlWorker::start(std::move(shared).value())
                         : Result<std::unique_ptr<GlWorker>>(shared.error());
    if (worker) {
      scene->mGlWorker = std::move(worker).value();
      scene->mStore.setWorker(scene->mGlWorker.get());
    } else if (scene->mOptions.log) {
      scene->mOptions.log("GPU memory is made when needed (" + worker.error().message + ")");
    }
  }
  // The loader pool and the clock are the driver's; the kinds registered are what this
  // renderer draws. Reads the roots.
  ChunkKinds kinds;
  scene->mDrawnKinds.push_back(&scene->mStaticKind);
  const auto& nodes = scene->mTileset->nodes();
  if (std::any_of(nodes.begin(), nodes.end(),
                  [](const NodeRecord& r) { return r.meshKind == MeshKind::kVipm; })) {
    auto vipm = VipmChunkKind::create(*scene->mTileset);
    if (!vipm) return vipm.error();
    scene->mVipmKind = std::move(vipm).value();
    scene->mDrawnKinds.push_back(scene->mVipmKind.get());
  }
  for (DrawnChunkKind<TerrainFrame>* kind : scene->mDrawnKinds) kinds.add(*kind);
  FrameDriverOptions d;
  d.cacheBytes = scene->mOptions.cacheBytes;
  d.maxInFlight = std::max(1u, scene->mOptions.loadsInFlight);
  d.uploadMillisecondsPerFrame = scene->mOptions.uploadMillisecondsPerFrame;
  d.completeness =
      scene->mOptions.complete ? FrameCompleteness::kComplete : FrameCompleteness::kStreaming;
  d.log = scene->mOptions.log;
  auto driver = FrameDriver::create(*scene->mTileset, scene->mTree, std::move(kinds), *scene->mPool,
                                    scene->mClock, std::move(d));
  if (!driver) return driver.error();
  scene->mDriver = std::move(driver).value();
  return scene;
}

TerrainScene::TerrainScene(std::unique_ptr<TilesetReader> tileset, ChunkTree tree,
                           TerrainRenderer renderer, SceneOptions options)
    : mTileset(std::move(tileset)),
      mTree(std::move(tree)),
      mOptions(std::move(options)),
      mRenderer(std::move(renderer)),
      mStaticKind(
          mStore, mRenderer,
          mTileset->header().textured() ? ChunkTextures::kRequired : ChunkTextures::kOptional,
          mOptions.horizonCulling),
      mPool(std::make_unique<ThreadPool>(std::max(1u, mOptions.loaderThreads))) {}

TerrainScene::~TerrainScene() {
  mDriver.reset();  // waits for running loads
  mPool.reset();
  mGlWorker.reset();  // before the store, which deletes what the worker made and left
}

DrawStats TerrainScene::drawSelection(const View& view, std::span<const SelectedChunk> chunks,
                                      const TerrainStyle& style,
                                      const SelectionOptions& selection) {
  // Clear and sky; each kind's opaque draws; composited layers and overlays.
  DrawStats stats;
  const FrameContext context = mRenderer.beginFrame(view, style, mTree, stats);
  SelectionOptions options = selection;
  options.drawable = {};
  TerrainFrame frame{context, mTree, stats, options};
  mRuns.split(mTree, chunks);
  for (const KindRuns::Run& run : mRuns.runs())
    for (DrawnChunkKind<TerrainFrame>* kind : mDrawnKinds)
      if (kind->meshKind() == run.kind) kind->addDraws(frame, run.chunks);
  mRenderer.finishFrame(context, mTree, chunks, mStore, stats);
  return stats;
}

Result<FrameStats> TerrainScene::renderFrame(const View& view, const SelectionOptions& options,
                                             const TerrainStyle& style, bool reselect) {
  FrameStats stats;
  if (reselect) {
    const UpdateStats update = mDriver->update(view, options);
    stats.selectMicroseconds = update.selectMicroseconds;
    stats.uploadMilliseconds = update.uploadMilliseconds;
    stats.uploads = update.uploads;
    stats.deferredUploads = update.deferredUploads;
    stats.evictions = update.evictions;
    stats.waitedOnIo = update.waitedOnIo;
    stats.easing = update.easing;
  }
  stats.selection = mDriver->lastSelection();
  if (mVipmKind) stats.reconstructMs = mVipmKind->takeReconstructMs();
  if (stats.selection.undrawableRoots > 0 && stats.selection.selected == 0)
    return makeError(mTileset->name(), "no chunk can be drawn");
  if (mVipmKind) mVipmKind->takeFanTimings();  // other views' (bench's look-down images)
  stats.draw =
      drawSelection(view, visibleChunks(view, mDriver->selected(), style, stats), style, options);
  if (mVipmKind)
    for (VipmChunkKind::FanTiming& t : mVipmKind->takeFanTimings()) {
      stats.fanFrameMs = std::isnan(stats.fanFrameMs) ? t.totalMs : stats.fanFrameMs + t.totalMs;
      stats.fanChangeMs.insert(stats.fanChangeMs.end(), t.changedMs.begin(), t.changedMs.end());
    }
  return stats;
}

FrameStats TerrainScene::renderResident(const View& view, const SelectionOptions& selection,
                                        const TerrainStyle& style) {
  FrameStats stats;
  SelectionOptions options = selection;
  options.drawable = mDriver->residency().drawable();
  mOtherView.reserve(mTree.nodes().size());
  stats.selection = selectChunks(mTree, view, options, mOtherView);
  stats.draw = drawSelection(view, visibleChunks(view, mOtherView, style, stats), style, selection);
  return stats;
}

std::span<const SelectedChunk> TerrainScene::visibleChunks(const View& view,
                                                           std::span<const SelectedChunk> selected,
                                                           const TerrainStyle& style,
                                                           FrameStats& stats) {
  if (mOptions.horizonCulling == HorizonCulling::kOff || !style.skirts) return selected;
  stats.horizon = mDriver->cullHidden(view, selected, kNearPlane, mVisible);
  return mVisible;
}

DrawStats TerrainScene::drawChunks(const View& view, std::span<const SelectedChunk> chunks,
                                   const TerrainStyle& style, const SelectionOptions& selection) {
  return drawSelection(view, chunks, style, selection);
}

DrawStats TerrainScene::drawVipmMaterials(const View& view, std::span<const VipmChunkAt> chunks,
                                          const TerrainStyle& style,
                                          const SelectionOptions& selection) {
  DrawStats stats;
  if (!mVipmKind) {
    stats.missing = uint32_t(chunks.size());
    return stats;
  }
  // Black (material code 0) where nothing is drawn; no sky, overlays or layers.
  TerrainStyle ids;
  ids.skirts = style.skirts;
  ids.sky = false;
  ids.haze = 0.0;
  ids.textures = false;
  ids.background = {0, 0, 0};
  const FrameContext context = mRenderer.beginFrame(view, ids, mTree, stats);
  SelectionOptions options = selection;
  options.drawable = {};
  TerrainFrame frame{context, mTree, stats, options};
  mVipmKind->addMaterialIdDraws(frame, chunks);
  glDisable(GL_DEPTH_TEST);
  glBindVertexArray(0);
  return stats;
}

void TerrainScene::replaceNodes(std::vector<NodeReplacement> nodes,
                                std::span<const double> levelErrors) {
  for (const NodeReplacement& n : nodes) mTree.updateNode(n.node, n.record);
  for (size_t level = 0; level < levelErrors.size(); ++level)
    mTree.setLevelError(uint32_t(level), levelErrors[level]);
  mDriver->replaceNodes(std::move(nodes));
}

}  // namespace terralod
