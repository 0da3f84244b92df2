#include "terralod/render/terrain_scene.h"

#include <algorithm>
#include <nlohmann/json.hpp>
#include <thread>

namespace terralod {
namespace {

using Clock = std::chrono::steady_clock;
double millisecondsSince(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

// A static RTIN chunk as the loaders decode it.
struct StaticChunkPayload final : ChunkPayload {
  ChunkData data;
};

uint64_t decodedBytes(const ChunkData& d) {
  uint64_t bytes = 0;
  for (const ChunkPart& p : d.geometry.parts)
    bytes += p.vertices.size() * sizeof(ChunkVertex) + p.indices.size() * sizeof(uint32_t);
  if (d.texture) bytes += d.texture->bytes();
  return bytes;
}

}  // namespace

Result<std::unique_ptr<TerrainScene>> TerrainScene::create(std::unique_ptr<TilesetReader> tileset,
                                                           SceneOptions options) {
  for (const NodeRecord& n : tileset->nodes())
    if (n.meshKind != MeshKind::kStaticRtin)
      return makeError(tileset->name(), "chunk mesh kind " + std::to_string(int(n.meshKind)) +
                                            " is not supported by this renderer");
  auto renderer = TerrainRenderer::create();
  if (!renderer) return renderer.error();
  {
    // Each level's tile sizes (metadata "texture": "levels"): where the mips keep their texels.
    const auto meta = nlohmann::json::parse(tileset->metadataJson(), nullptr, false);
    std::vector<uint32_t> colorSizes, normalSizes;
    if (meta.is_object() && meta.contains("texture") && meta["texture"].is_object() &&
        meta["texture"].contains("levels") && meta["texture"]["levels"].is_array()) {
      for (const auto& level : meta["texture"]["levels"]) {
        const auto size = [&](const char* key) -> uint32_t {
          if (!level.is_object() || !level.contains(key) || !level[key].is_number_unsigned())
            return 0;
          const uint64_t v = level[key].get<uint64_t>();
          return v >= 2 && v <= kMaxTextureSize ? uint32_t(v) : 0;
        };
        colorSizes.push_back(size("color_size"));
        normalSizes.push_back(size("normal_size"));
      }
    }
    // Sizes that are not all there, or not one per level, are not used.
    const bool usable = colorSizes.size() == tileset->header().levelCount &&
                        std::find(colorSizes.begin(), colorSizes.end(), 0) == colorSizes.end() &&
                        std::find(normalSizes.begin(), normalSizes.end(), 0) == normalSizes.end();
    if (usable) renderer->setTextureSizes(colorSizes, normalSizes);
  }
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
  if (Status s = scene->loadRoots(); !s) return s.error();
  return scene;
}

TerrainScene::TerrainScene(std::unique_ptr<TilesetReader> tileset, ChunkTree tree,
                           TerrainRenderer renderer, SceneOptions options)
    : mTileset(std::move(tileset)),
      mTree(std::move(tree)),
      mOptions(std::move(options)),
      mRenderer(std::move(renderer)),
      mPool(std::make_unique<ThreadPool>(std::max(1u, mOptions.loaderThreads))) {
  mSelected.reserve(mTree.nodes().size());
  mDrawnFrame.assign(mTree.nodes().size(), 0);
  mEntryMorph.assign(mTree.nodes().size(), 0.0f);
  const TilesetReader* reader = mTileset.get();
  const bool textured = reader->header().textured();
  auto load = [reader, textured](uint32_t node) -> Result<LoadedChunk> {
    auto data = reader->readChunkData(node);
    if (!data) return data.error();
    if (textured && (!data->texture || !data->texture->find(TextureLayerKind::kColor) ||
                     !data->texture->find(TextureLayerKind::kNormal)))
      return makeError(reader->name(),
                       "chunk " + std::to_string(node) + " lacks its colour or normal texture");
    auto payload = std::make_unique<StaticChunkPayload>();
    payload->data = std::move(data).value();
    LoadedChunk loaded;
    loaded.bytes = decodedBytes(payload->data);
    loaded.bytesRead = payload->data.bytesRead;
    loaded.payload = std::move(payload);
    return loaded;
  };
  ResidencyOptions r;
  r.budgetBytes = mOptions.cacheBytes;
  r.maxInFlight = std::max(2u, 2 * mOptions.loaderThreads);
  mResidency = std::make_unique<Residency>(mTree, load, *mPool, r, mOptions.log);
}

TerrainScene::~TerrainScene() {
  mResidency.reset();  // waits for running loads
  mPool.reset();
  mGlWorker.reset();  // before the store, which deletes what the worker made and left
}

Status TerrainScene::loadRoots() {
  for (uint32_t root = 0; root < mTree.rootCount(); ++root) {
    auto loaded = mResidency->loadNow(root);
    if (!loaded) return loaded.error();
    const auto& data = static_cast<const StaticChunkPayload&>(*loaded->payload).data;
    mStore.upload(root, data.geometry, data.texture ? &*data.texture : nullptr);
    mResidency->markLoadedNow(root, mStore.find(root)->bytes);
  }
  return {};
}

void TerrainScene::upload(const ReadyChunk& chunk) {
  const auto& data = static_cast<const StaticChunkPayload&>(*chunk.chunk.payload).data;
  mStore.upload(chunk.node, data.geometry, data.texture ? &*data.texture : nullptr);
  mResidency->markResident(chunk, mStore.find(chunk.node)->bytes);
}

void TerrainScene::step(const View& view, const SelectionOptions& selection, FrameStats& stats,
                        bool unlimitedUploads) {
  Residency& residency = *mResidency;
  // Uploads, most wanted first, within the frame's budget (always at least one).
  const auto uploadStart = Clock::now();
  mStore.poll();
  std::vector<ReadyChunk> ready = residency.collect();
  for (ReadyChunk& chunk : ready) {
    if (!unlimitedUploads && stats.uploads > 0 &&
        millisecondsSince(uploadStart) > mOptions.uploadMillisecondsPerFrame) {
      residency.returnReady(std::move(chunk));
      continue;
    }
    const auto& data = static_cast<const StaticChunkPayload&>(*chunk.chunk.payload).data;
    if (!mStore.reserve(data.geometry, data.texture ? &*data.texture : nullptr)) {
      residency.returnReady(std::move(chunk));  // its GPU memory is being made
      ++stats.deferredUploads;
      continue;
    }
    upload(chunk);
    ++stats.uploads;
  }
  stats.uploadMilliseconds = millisecondsSince(uploadStart);

  const auto selectStart = Clock::now();
  SelectionOptions options = selection;
  options.drawable = residency.drawable();
  mLastSelection = selectChunks(mTree, view, options, mSelected);
  stats.selectMicroseconds =
      std::chrono::duration<double, std::micro>(Clock::now() - selectStart).count();
  // A split the selection makes now that last frame drew the parent: the children start at
  // the parent's surface. On time (the children's ρ <= τ/2) that is their schedule anyway and
  // any t keeps the error within τ; late, it hides the pop while they ease in. (Not for
  // complete frames: they show the settled selection.)
  constexpr float kEntryStep = 1.0f / 16.0f;
  for (SelectedChunk& c : mSelected) {
    const uint32_t parent = mTree.node(c.node).parent;
    const bool drawnLastFrame = mDrawnFrame[c.node] + 1 == mFrame;
    if (!mOptions.complete && selection.morph && parent != kNoNode && !drawnLastFrame &&
        mDrawnFrame[parent] + 1 == mFrame)
      mEntryMorph[c.node] = 1.0f;
    else if (!drawnLastFrame)
      mEntryMorph[c.node] = 0.0f;  // an easing cut short (it split again) does not come back
    if (mEntryMorph[c.node] > 0.0f) {
      if (mEntryMorph[c.node] > c.morph) ++stats.easing;
      c.morph = std::max(c.morph, mEntryMorph[c.node]);
      mEntryMorph[c.node] = std::max(0.0f, mEntryMorph[c.node] - kEntryStep);
    }
    mDrawnFrame[c.node] = mFrame;
  }
  ++mFrame;
  // In use: the drawn chunks and their ancestors. Wanted: the children of chunks drawn
  // coarser than wanted (nearest first), then those of chunks close to splitting (prefetch).
  for (const SelectedChunk& s : mSelected) {
    for (uint32_t i = s.node; i != kNoNode; i = mTree.node(i).parent) residency.touch(i);
    const ChunkNode& n = mTree.node(s.node);
    if (n.childCount == 0) continue;
    const double rho =
        screenSpaceError(view, mTree.levelError(n.level), distanceToBox(view.camera.eye, n.box));
    if (rho <= 0.5 * selection.tau) continue;
    const float priority = float(selection.tau / rho) + (rho > selection.tau ? 0.0f : 1.0f);
    for (uint32_t c = n.firstChild; c < n.firstChild + n.childCount; ++c)
      residency.request(c, priority);
  }
  for (uint32_t node : residency.evict()) {
    mStore.release(node);
    ++stats.evictions;
  }
  residency.dispatch();
}

Result<FrameStats> TerrainScene::renderFrame(const View& view, const SelectionOptions& options,
                                             const TerrainStyle& style, bool reselect) {
  FrameStats stats;
  if (reselect) {
    step(view, options, stats, mOptions.complete);
    // Complete frames wait until nothing they want is still on its way.
    for (int round = 0; mOptions.complete && mLastSelection.coarserThanWanted > 0 && round < 100000;
         ++round) {
      // Nothing on its way: the rest failed (retried later) or does not fit the budget.
      // (Chunks whose GPU memory is being made are on their way too.)
      if (mResidency->inFlight() == 0 && mResidency->readyWaiting() == 0 &&
          (mResidency->queued() == 0 || round > 0))
        break;
      std::this_thread::sleep_for(std::chrono::microseconds(200));
      stats.waitedOnIo = true;
      FrameStats more;
      step(view, options, more, true);
      stats.uploads += more.uploads;
      stats.evictions += more.evictions;
      stats.uploadMilliseconds += more.uploadMilliseconds;
    }
  }
  stats.selection = mLastSelection;
  if (stats.selection.undrawableRoots > 0 && stats.selection.selected == 0)
    return makeError(mTileset->name(), "no chunk can be drawn");
  stats.draw =
      mRenderer.draw(view, mTree, visibleChunks(view, mSelected, style, stats), mStore, style);
  return stats;
}

FrameStats TerrainScene::renderResident(const View& view, const SelectionOptions& selection,
                                        const TerrainStyle& style) {
  FrameStats stats;
  SelectionOptions options = selection;
  options.drawable = mResidency->drawable();
  mOtherView.reserve(mTree.nodes().size());
  stats.selection = selectChunks(mTree, view, options, mOtherView);
  stats.draw =
      mRenderer.draw(view, mTree, visibleChunks(view, mOtherView, style, stats), mStore, style);
  return stats;
}

std::span<const SelectedChunk> TerrainScene::visibleChunks(const View& view,
                                                           std::span<const SelectedChunk> selected,
                                                           const TerrainStyle& style,
                                                           FrameStats& stats) {
  if (mOptions.horizonCulling == HorizonCulling::kOff || !style.skirts) return selected;
  stats.horizon = mHorizonCuller.cull(mTree, view, selected, kNearPlaneMetres, mVisible);
  return mVisible;
}

DrawStats TerrainScene::drawChunks(const View& view, std::span<const SelectedChunk> chunks,
                                   const TerrainStyle& style) {
  return mRenderer.draw(view, mTree, chunks, mStore, style);
}

}  // namespace terralod
