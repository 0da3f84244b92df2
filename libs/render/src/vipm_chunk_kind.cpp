#include "terralod/render/vipm_chunk_kind.h"

#include <algorithm>
#include <cassert>
#include <chrono>
#include <utility>
#include <vector>

#include "terralod/runtime/view.h"
#include "terralod/vipm/vipm_fans.h"
#include "terralod/vipm/vipm_theta.h"
#include "vipm_gpu_chunk.h"
#include "vipm_pass.h"
#include "vipm_payload.h"

namespace terralod {
namespace {

struct Payload final : ChunkPayload {
  VipmChunkPayload chunk;
};

// Sides of a node's chunk that meet another chunk (not the data's edge): those get flanges.
uint8_t flangeSides(const TilesetHeader& h, const NodeRecord& r) {
  const uint64_t cells = h.chunkCells(r.level);
  uint8_t sides = 0;
  if (r.x > 0) sides |= kFlangeWest;
  if (r.y > 0) sides |= kFlangeSouth;
  if ((uint64_t(r.x) + 1) * cells < uint64_t(h.sourceColumns) - 1) sides |= kFlangeEast;
  if ((uint64_t(r.y) + 1) * cells < uint64_t(h.sourceRows) - 1) sides |= kFlangeNorth;
  return sides;
}

// Where blots begin (TerrainStyle::blotCellPixels) and materials fade toward them.
VipmBlotDistances vipmBlotDistances(const ChunkTree& tree, const View& view,
                                    const TerrainStyle& style) {
  VipmBlotDistances d;
  if (style.blots == VipmBlots::kOff || !(style.blotCellPixels > 0)) return d;
  // A cell of `spacing` metres covers blotCellPixels at distance spacing·K / blotCellPixels.
  const double perMetreAtOne = screenSpaceError(view, 1.0, 1.0);
  const auto spacing = tree.spacing();
  d.blotFrom = std::min(spacing[0], spacing[1]) * perMetreAtOne / style.blotCellPixels;
  d.fadeFrom = 0.5 * d.blotFrom;
  return d;
}

}  // namespace

double vipmDrawnTheta(const ChunkTree& tree, const View& view, double tau,
                      const SelectedChunk& chunk) {
  const ChunkNode& n = tree.node(chunk.node);
  // τ·D/K with D as the selection measures it (screenSpaceError(δ) = δ·K/D).
  const double distance = distanceToBox(view.camera.eye, n.box);
  const double perMetre = screenSpaceError(view, 1.0, distance);
  const double allowance = tau / perMetre;
  const double own = tree.levelError(n.level);
  const double parent = n.level > 0 ? tree.levelError(n.level - 1) : own;
  return vipmTheta(allowance, chunk.morph, own, parent);
}

Result<std::unique_ptr<VipmChunkKind>> VipmChunkKind::create(const TilesetReader& tileset) {
  auto pass = VipmPass::create(tileset.metadata().materials);
  if (!pass) return pass.error();
  return std::unique_ptr<VipmChunkKind>(
      new VipmChunkKind(tileset, std::make_unique<VipmPass>(std::move(pass).value())));
}

VipmChunkKind::VipmChunkKind(const TilesetReader& tileset, std::unique_ptr<VipmPass> pass)
    : mTileset(tileset), mPass(std::move(pass)), mStitchTable(std::make_unique<StitchTable>()) {}

VipmChunkKind::~VipmChunkKind() = default;

Result<LoadedChunk> VipmChunkKind::decode(const ChunkBlob& blob) const {
  const TilesetHeader& h = mTileset.header();
  const NodeRecord& record = blob.record;  // an edit's, when the node was replaced
  const auto start = std::chrono::steady_clock::now();
  auto decoded = decodeVipmPayload(
      blob.bytes, blob.tilesetName + " chunk " + std::to_string(blob.node),
      uint32_t(h.chunkCells(record.level)), flangeSides(h, record), record.maxSkirtDepth,
      int64_t(record.x) * h.chunkCells(record.level),
      int64_t(record.y) * h.chunkCells(record.level), uint32_t(h.chunkCells(0)), mPass->averages());
  if (!decoded) return decoded.error();
  const double ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  {
    std::lock_guard lock(mTimingMutex);
    mReconstructMs.push_back(ms);
  }
  auto payload = std::make_unique<Payload>();
  payload->chunk = std::move(decoded).value();
  LoadedChunk loaded;
  loaded.bytes = payload->chunk.bytes();
  loaded.payload = std::move(payload);
  return loaded;
}

VipmChunkKind::BlockKey VipmChunkKind::blockKey(int64_t cornerX, int64_t cornerY, uint32_t cells) {
  const int64_t side = int64_t(std::max(cells, 1u)) * VipmBlock::kSide;
  return {cells, cornerX / side, cornerY / side};
}

uint64_t VipmChunkKind::upload(uint32_t node, const ChunkPayload& payload) {
  const VipmChunkPayload& p = static_cast<const Payload&>(payload).chunk;
  const StitchChunk& where = p.stitcher.chunk();
  const BlockKey key = blockKey(where.cornerX, where.cornerY, p.cells);
  std::unique_ptr<VipmBlock>& block = mBlocks[key];
  if (!block)
    block = std::make_unique<VipmBlock>(p.normals.size, p.normals.encoding,
                                        uint32_t(p.normals.mips.size()));
  assert(block->fits(p.normals));  // one level's chunks: the same normal map size
  const int64_t cells = int64_t(p.cells);
  const int slot = int((where.cornerX / cells) % VipmBlock::kSide +
                       VipmBlock::kSide * ((where.cornerY / cells) % VipmBlock::kSide));
  auto chunk = std::make_unique<VipmGpuChunk>(p, *block, slot);
  block->setMember(slot, chunk.get());
  const uint64_t bytes = chunk->bytes();
  mGpuBytes += chunk->gpuBytes();
  mBlockBytesUsed += chunk->blockBytes();
  if (auto& old = mChunks[node]) {
    mGpuBytes -= old->gpuBytes();
    mBlockBytesUsed -= old->blockBytes();
  }
  mChunks[node] = std::move(chunk);  // an old chunk in the slot releases its vertices
  return bytes;
}

uint64_t VipmChunkKind::blockSpareBytes() const {
  uint64_t blocks = 0;
  for (const auto& [key, block] : mBlocks) blocks += block->allocatedBytes();
  return blocks > mBlockBytesUsed ? blocks - mBlockBytesUsed : 0;
}

bool VipmChunkKind::updateRecord(uint32_t node, const NodeRecord& record) {
  auto it = mChunks.find(node);
  if (it == mChunks.end()) return false;
  it->second->setFlangeDepth(record.maxSkirtDepth);
  return true;
}

void VipmChunkKind::release(uint32_t node) {
  auto it = mChunks.find(node);
  if (it == mChunks.end()) return;
  VipmGpuChunk& chunk = *it->second;
  const BlockKey key = blockKey(chunk.cornerX(), chunk.cornerY(), chunk.cells());
  VipmBlock& block = chunk.block();
  if (block.member(chunk.slot()) == &chunk) block.setMember(chunk.slot(), nullptr);
  mGpuBytes -= chunk.gpuBytes();
  mBlockBytesUsed -= chunk.blockBytes();
  mChunks.erase(it);
  if (block.empty()) mBlocks.erase(key);
}

void VipmChunkKind::stitch(const TerrainStyle& style, std::span<const VipmDraw> draws) {
  const bool fans = style.skirts && style.stitch == VipmStitch::kFans;
  if (!fans) {
    for (const VipmDraw& d : draws) d.chunk->stitch(nullptr);
    return;
  }
  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  mStitchTable->clear();
  for (const VipmDraw& d : draws) d.chunk->addStitchPoints(*mStitchTable);
  mStitchTable->finish();
  FanTiming timing;
  for (const VipmDraw& d : draws) {
    const auto before = Clock::now();
    if (d.chunk->stitch(mStitchTable.get()))
      timing.changedMs.push_back(
          std::chrono::duration<double, std::milli>(Clock::now() - before).count());
  }
  timing.totalMs = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
  mFanTimings.push_back(std::move(timing));
}

std::vector<VipmChunkKind::FanTiming> VipmChunkKind::takeFanTimings() {
  return std::exchange(mFanTimings, {});
}

std::vector<double> VipmChunkKind::takeReconstructMs() {
  std::lock_guard lock(mTimingMutex);
  return std::exchange(mReconstructMs, {});
}

uint32_t VipmChunkKind::appliedCollapses(uint32_t node) const {
  auto it = mChunks.find(node);
  return it == mChunks.end() ? 0 : it->second->applied();
}

void VipmChunkKind::addDraws(TerrainFrame& frame, std::span<const SelectedChunk> chunks) {
  const ChunkTree& tree = frame.tree;
  const View& view = frame.context.view;
  const Geomorph geomorph = frame.selection.morph ? Geomorph::kOn : Geomorph::kOff;
  const VipmBlotDistances blots = vipmBlotDistances(tree, view, frame.context.style);
  std::vector<VipmDraw>& draws = mDraws;
  draws.clear();
  for (const SelectedChunk& s : chunks) {
    auto it = mChunks.find(s.node);
    if (it == mChunks.end()) {
      ++frame.stats.missing;
      continue;
    }
    ++frame.stats.chunks;
    const double theta = vipmDrawnTheta(tree, view, frame.selection.tau, s);
    it->second->update(theta, geomorph);
    const bool blot = frame.context.style.blots == VipmBlots::kOn &&
                      distanceToBox(view.camera.eye, tree.node(s.node).box) >= blots.blotFrom;
    draws.push_back({it->second.get(), s.node, s.morph, blot});
    frame.stats.blots += blot;
  }
  stitch(frame.context.style, draws);
  mPass->draw(frame.context, tree, draws, frame.stats, VipmImage::kColour, blots);
}

void VipmChunkKind::addMaterialIdDraws(TerrainFrame& frame, std::span<const VipmChunkAt> chunks) {
  const Geomorph geomorph = frame.selection.morph ? Geomorph::kOn : Geomorph::kOff;
  std::vector<VipmDraw>& draws = mDraws;
  draws.clear();
  for (const VipmChunkAt& c : chunks) {
    auto it = mChunks.find(c.node);
    if (it == mChunks.end()) {
      ++frame.stats.missing;
      continue;
    }
    ++frame.stats.chunks;
    it->second->update(c.theta, c.morphTheta, geomorph);
    draws.push_back({it->second.get(), c.node, 0.0f});
  }
  stitch(frame.context.style, draws);
  mPass->draw(frame.context, frame.tree, draws, frame.stats, VipmImage::kMaterialIds);
}

}  // namespace terralod
