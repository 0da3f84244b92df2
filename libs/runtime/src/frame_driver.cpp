#include "terralod/runtime/frame_driver.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace terralod {

Result<std::unique_ptr<FrameDriver>> FrameDriver::create(const TilesetReader& tileset,
                                                         const ChunkTree& tree, ChunkKinds kinds,
                                                         TaskRunner& runner, FrameClock& clock,
                                                         FrameDriverOptions options) {
  if (Status s = kinds.covers(tree, tileset.name()); !s) return s.error();
  std::unique_ptr<FrameDriver> driver(
      new FrameDriver(tileset, tree, std::move(kinds), runner, clock, std::move(options)));
  if (Status s = driver->loadRoots(); !s) return s.error();
  // Roots are never evicted: when they alone fill the budget, nothing finer can ever load.
  const uint64_t roots = driver->mResidency->counters().residentBytes;
  if (roots >= driver->mOptions.cacheBytes && driver->mTree.levelCount() > 1 &&
      driver->mOptions.log) {
    char text[420];
    std::snprintf(text, sizeof text,
                  "%s: its %u roots alone take %.0f MB of the %.0f MB chunk budget, so no finer "
                  "chunk will load; give a larger budget (--cache-mb %.0f or more)%s",
                  tileset.name().c_str(), unsigned(tree.rootCount()), double(roots) / 1048576.0,
                  double(driver->mOptions.cacheBytes) / 1048576.0,
                  std::ceil(2.0 * double(roots) / 1048576.0 / 256.0) * 256.0,
                  tileset.header().meshKind == MeshKind::kVipm
                      ? ", or rebuild it with --upper-levels auto (one top node stays resident)"
                      : "");
    driver->mOptions.log(text);
  }
  return driver;
}

FrameDriver::FrameDriver(const TilesetReader& tileset, const ChunkTree& tree, ChunkKinds kinds,
                         TaskRunner& runner, FrameClock& clock, FrameDriverOptions options)
    : mTileset(tileset),
      mTree(tree),
      mKinds(std::move(kinds)),
      mClock(clock),
      mOptions(std::move(options)) {
  mSelected.reserve(mTree.nodes().size());
  mDrawnFrame.assign(mTree.nodes().size(), 0);
  mAncestorFrame.assign(mTree.nodes().size(), 0);
  mEntryMorph.assign(mTree.nodes().size(), 0.0f);
  mOccluders.resize(mTree.nodes().size());
  // Runs on loader threads: reads the node's bytes and has its kind decode them. Touches
  // only the reader (thread-safe) and the kinds' decode (thread-safe by contract).
  auto load = [reader = &mTileset, tree = &mTree, kinds = &mKinds,
               replacements = mReplacements](uint32_t node) -> Result<LoadedChunk> {
    std::shared_ptr<const NodeReplacement> replaced;
    {
      std::lock_guard lock(replacements->mutex);
      if (auto it = replacements->nodes.find(node); it != replacements->nodes.end())
        replaced = it->second;
    }
    const ChunkKind* kind = kinds->find(tree->node(node).meshKind);  // checked by create()
    Result<NodeBytes> read = replaced ? Result<NodeBytes>(replaced->bytes) : reader->readNode(node);
    if (!read) return read.error();
    auto loaded = kind->decode(ChunkBlob{node, *read, reader->name(),
                                         replaced ? replaced->record : reader->nodes()[node]});
    if (!loaded) return loaded.error();
    loaded->bytesRead = replaced ? 0 : read->bytes.size();
    if (!loaded->occluders.empty()) loaded->bytes += loaded->occluders.bytes();
    return loaded;
  };
  ResidencyOptions r;
  r.budgetBytes = mOptions.cacheBytes;
  r.maxInFlight = mOptions.maxInFlight;
  mResidency = std::make_unique<Residency>(mTree, load, runner, r, mOptions.log);
}

FrameDriver::~FrameDriver() = default;

ChunkKind& FrameDriver::kindOf(uint32_t node) {
  return *mKinds.find(mTree.node(node).meshKind);
}

Status FrameDriver::loadRoots() {
  for (uint32_t root = 0; root < mTree.rootCount(); ++root) {
    auto loaded = mResidency->loadNow(root);
    if (!loaded) return loaded.error();
    const uint64_t bytes = kindOf(root).upload(root, *loaded->payload);
    const uint64_t grid = loaded->occluders.empty() ? 0 : loaded->occluders.bytes();
    mResidency->markLoadedNow(root, bytes + grid);
    keepOccluders(root, std::move(loaded->occluders));
  }
  noteSharedBytes();
  return {};
}

void FrameDriver::noteSharedBytes() {
  uint64_t shared = 0;
  for (const ChunkKind* kind : mKinds.all()) shared += kind->sharedBytes();
  mResidency->setSharedBytes(shared);
}

void FrameDriver::uploadReady(UploadLimit limit, UpdateStats& stats) {
  // Most wanted first, within the frame's budget (always at least one).
  Residency& residency = *mResidency;
  const double start = mClock.nowMilliseconds();
  for (ChunkKind* kind : mKinds.all()) kind->beginFrame();
  std::vector<ReadyChunk> ready = residency.collect();
  for (ReadyChunk& chunk : ready) {
    if (limit == UploadLimit::kBudget && stats.uploads > 0 &&
        mClock.nowMilliseconds() - start > mUploadBudget) {
      residency.returnReady(std::move(chunk));
      continue;
    }
    ChunkKind& kind = kindOf(chunk.node);
    if (kind.prepare(*chunk.chunk.payload) == UploadRoom::kMemoryOnItsWay) {
      residency.returnReady(std::move(chunk));
      ++stats.deferredUploads;
      continue;
    }
    const uint64_t sharedBefore = kind.sharedBytes();
    const uint64_t bytes = kind.upload(chunk.node, *chunk.chunk.payload);
    const uint64_t sharedAfter = kind.sharedBytes();
    const uint64_t grown = sharedAfter > sharedBefore ? sharedAfter - sharedBefore : 0;
    const OccluderGrid& grid = chunk.chunk.occluders;
    if (chunk.refresh)
      residency.markRefreshed(chunk, bytes + (grid.empty() ? 0 : grid.bytes()));
    else
      residency.markResident(chunk, bytes + (grid.empty() ? 0 : grid.bytes()), grown);
    keepOccluders(chunk.node, std::move(chunk.chunk.occluders));
    ++stats.uploads;
  }
  stats.uploadMilliseconds = mClock.nowMilliseconds() - start;
}

void FrameDriver::easeLateSplits(const SelectionOptions& selection, FrameCompleteness completeness,
                                 UpdateStats& stats) {
  // A split the selection makes now that last frame drew the parent: the children start at
  // the parent's surface. On time (the children's ρ <= τ/2) that is their schedule anyway and
  // any t keeps the error within τ; late, it hides the pop while they ease in. (Not for
  // complete frames: they show the settled selection.) A split on time still starts a hair
  // above its schedule: the parent's ρ passed τ somewhere between the last frame and this
  // one, so the nearest child's schedule is 1 less about the camera's relative approach in
  // one frame (times own/(parent − own) + 1). Only a chunk more than kOnTime above its
  // schedule counts as easing (coarser than wanted), or every frame with a split would.
  constexpr float kEntryStep = 1.0f / 16.0f, kOnTime = 1.0f / 64.0f;
  const bool easeIn = completeness == FrameCompleteness::kStreaming && selection.morph;
  for (SelectedChunk& c : mSelected) {
    const uint32_t parent = mTree.node(c.node).parent;
    const bool drawnLastFrame = mDrawnFrame[c.node] + 1 == mFrame;
    if (easeIn && parent != kNoNode && !drawnLastFrame && mDrawnFrame[parent] + 1 == mFrame)
      mEntryMorph[c.node] = 1.0f;
    else if (!drawnLastFrame)
      mEntryMorph[c.node] = 0.0f;  // an easing cut short (it split again) does not come back
    if (mEntryMorph[c.node] > 0.0f) {
      if (mEntryMorph[c.node] > c.morph + kOnTime) ++stats.easing;
      c.morph = std::max(c.morph, mEntryMorph[c.node]);
      mEntryMorph[c.node] = std::max(0.0f, mEntryMorph[c.node] - kEntryStep);
    }
    mDrawnFrame[c.node] = mFrame;
  }
  ++mFrame;
}

void FrameDriver::requestWanted(const View& view, const SelectionOptions& selection) {
  // In use: the drawn chunks, their ancestors and every child of those ancestors (a chunk
  // splits only while all its children are resident, those out of view too: evicting one
  // would merge it, want the child again, load it, split and evict it, over and over).
  // Wanted: the children of chunks drawn coarser than wanted (nearest first), then those of
  // chunks close to splitting (prefetch).
  Residency& residency = *mResidency;
  for (const SelectedChunk& s : mSelected) {
    residency.touch(s.node);
    for (uint32_t i = mTree.node(s.node).parent; i != kNoNode; i = mTree.node(i).parent) {
      if (mAncestorFrame[i] == mFrame) break;  // this ancestor's chain is done this step
      mAncestorFrame[i] = mFrame;
      residency.touch(i);
      const ChunkNode& a = mTree.node(i);
      for (uint32_t c = a.firstChild; c < a.firstChild + a.childCount; ++c) residency.touch(c);
    }
    const ChunkNode& n = mTree.node(s.node);
    if (n.childCount == 0) continue;
    const double rho =
        screenSpaceError(view, mTree.levelError(n.level), distanceToBox(view.camera.eye, n.box));
    if (rho <= 0.5 * selection.tau) continue;
    const float priority = float(selection.tau / rho) + (rho > selection.tau ? 0.0f : 1.0f);
    for (uint32_t c = n.firstChild; c < n.firstChild + n.childCount; ++c)
      residency.request(c, priority);
  }
}

void FrameDriver::step(const View& view, const SelectionOptions& selection,
                       FrameCompleteness completeness, UploadLimit limit, UpdateStats& stats) {
  uploadReady(limit, stats);
  noteSharedBytes();

  const double selectStart = mClock.nowMilliseconds();
  SelectionOptions options = selection;
  options.drawable = mResidency->drawable();
  mLastSelection = selectChunks(mTree, view, options, mSelected);
  stats.selectMicroseconds = (mClock.nowMilliseconds() - selectStart) * 1000.0;

  easeLateSplits(selection, completeness, stats);
  requestWanted(view, selection);
  for (uint32_t node : mResidency->evict()) {
    kindOf(node).release(node);
    keepOccluders(node, {});
    ++stats.evictions;
  }
  noteSharedBytes();
  mResidency->dispatch();
}

UpdateStats FrameDriver::update(const View& view, const SelectionOptions& selection,
                                FrameCompleteness completeness) {
  const bool complete = completeness == FrameCompleteness::kComplete;
  const double now = mClock.nowMilliseconds();
  const double interval = mLastUpdateStart < 0.0 ? 0.0 : now - mLastUpdateStart;
  mLastUpdateStart = now;
  mUploadBudget =
      std::max(mOptions.uploadMillisecondsPerFrame, mOptions.uploadFrameShare * interval);
  UpdateStats stats;
  step(view, selection, completeness, complete ? UploadLimit::kUnlimited : UploadLimit::kBudget,
       stats);
  // Complete frames wait until nothing they want is still on its way.
  for (int round = 0; complete && mLastSelection.coarserThanWanted > 0 && round < 100000; ++round) {
    // Nothing on its way: the rest failed (retried later) or does not fit the budget.
    // (Chunks whose GPU memory is being made are on their way too.)
    if (mResidency->inFlight() == 0 && mResidency->readyWaiting() == 0 &&
        (mResidency->queued() == 0 || round > 0))
      break;
    mClock.sleepMicroseconds(200);
    stats.waitedOnIo = true;
    UpdateStats more;
    step(view, selection, completeness, UploadLimit::kUnlimited, more);
    stats.uploads += more.uploads;
    stats.evictions += more.evictions;
    stats.uploadMilliseconds += more.uploadMilliseconds;
  }
  stats.selection = mLastSelection;
  return stats;
}

HorizonCullingStats FrameDriver::cullHidden(const View& view, std::span<const SelectedChunk> chunks,
                                            double nearPlane, std::vector<SelectedChunk>& visible) {
  return mCuller.cull(mTree, view, chunks, nearPlane, visible, mOccluders);
}

void FrameDriver::replaceNodes(std::vector<NodeReplacement> nodes) {
  for (NodeReplacement& r : nodes) {
    const uint32_t node = r.node;
    // A new record alone: an uploaded chunk with no refresh coming takes it in place.
    const bool inPlace = r.part == ReplacedPart::kRecord &&
                         mResidency->state(node) == ChunkState::kResident &&
                         !mResidency->stale(node) && kindOf(node).updateRecord(node, r.record);
    {
      std::lock_guard lock(mReplacements->mutex);
      mReplacements->nodes[node] = std::make_shared<const NodeReplacement>(std::move(r));
    }
    if (!inPlace) mResidency->invalidate(node);
  }
}

void FrameDriver::keepOccluders(uint32_t node, OccluderGrid grid) {
  OccluderGrid& kept = mOccluders[node];
  if (!kept.empty()) mOccluderBytes -= kept.bytes();
  kept = std::move(grid);
  if (!kept.empty()) mOccluderBytes += kept.bytes();
}

}  // namespace terralod
