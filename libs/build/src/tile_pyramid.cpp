#include "terralod/build/tile_pyramid.h"

#include <algorithm>
#include <array>
#include <bit>

namespace terralod {
namespace {

uint8_t childCount(const NodeRecord& n) {
  return uint8_t(std::popcount(unsigned(n.childMask)));
}

template <typename T>
std::vector<std::pair<uint32_t, T>> sortedByNode(std::vector<std::pair<uint32_t, T>>& items) {
  std::vector<std::pair<uint32_t, T>> out = std::move(items);
  items.clear();
  std::sort(out.begin(), out.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  return out;
}

}  // namespace

TilePyramid::TilePyramid(const TexturePass& pass, const std::vector<NodeRecord>& nodes,
                         std::vector<uint8_t> builds, TextureSink sink)
    : mPass(pass),
      mNodes(nodes),
      mBuilds(std::move(builds)),
      mSink(std::move(sink)),
      mMissing(nodes.size(), 0) {
  for (size_t i = 0; i < nodes.size(); ++i)
    if (mBuilds[i]) mMissing[i] = childCount(nodes[i]);
}

void TilePyramid::add(uint32_t node, ChunkTiles tiles) {
  for (;;) {
    mPass.keepWhatTheParentReads(node, tiles);
    const uint32_t parent = mNodes[node].parent;
    PartialTiles* partial = nullptr;
    {
      std::lock_guard lock(mMutex);
      if (parent == kNoNode || !mBuilds[parent]) {
        mFrontier.emplace_back(node, std::move(tiles));
        return;
      }
      partial = &mPartial[parent];
      mPass.startParent(parent, *partial, tiles);
    }
    // The parent's texels this child alone reaches, outside the lock (siblings concurrently).
    const NodeRecord& p = mNodes[parent];
    size_t quadrant = 0;
    for (uint32_t c = p.firstChild, q = 0; q < 4; ++q)
      if (p.childMask & (1u << q)) {
        if (c++ == node) quadrant = q;
      }
    mPass.addChild(*partial, quadrant, tiles);
    std::array<ChunkTiles, 4> siblings;
    std::array<ChunkTiles*, 4> children{};
    PartialTiles made0;
    {
      std::lock_guard lock(mMutex);
      if (--mMissing[parent] > 0) {
        mWaiting.emplace(node, std::move(tiles));
        return;
      }
      // The last child: take its siblings' tiles and finish the parent here.
      uint32_t c = p.firstChild;
      for (size_t q = 0; q < 4; ++q) {
        if (!(p.childMask & (1u << q))) continue;
        if (c == node) {
          siblings[q] = std::move(tiles);
        } else {
          auto it = mWaiting.find(c);
          siblings[q] = std::move(it->second);
          mWaiting.erase(it);
        }
        children[q] = &siblings[q];
        ++c;
      }
      auto it = mPartial.find(parent);
      made0 = std::move(it->second);
      mPartial.erase(it);
    }
    ChunkTiles made = mPass.finishParent(parent, made0, children);
    std::vector<uint8_t> texture = mPass.encode(parent, made);
    if (mSink) {
      mSink(parent, std::move(texture));
    } else {
      std::lock_guard lock(mMutex);
      mTextures.emplace_back(parent, std::move(texture));
    }
    node = parent;
    tiles = std::move(made);
  }
}

std::vector<std::pair<uint32_t, std::vector<uint8_t>>> TilePyramid::takeTextures() {
  std::lock_guard lock(mMutex);
  return sortedByNode(mTextures);
}

std::vector<std::pair<uint32_t, ChunkTiles>> TilePyramid::takeFrontier() {
  std::lock_guard lock(mMutex);
  return sortedByNode(mFrontier);
}

std::vector<uint8_t> TilePyramid::buildableFrom(const std::vector<NodeRecord>& nodes,
                                                int32_t blockLevel,
                                                const std::vector<uint32_t>& blocks) {
  // Block-level nodes below each node: all of them, and those given.
  std::vector<uint32_t> total(nodes.size(), 0), given(nodes.size(), 0);
  auto countUp = [&](uint32_t i, std::vector<uint32_t>& count) {
    for (uint32_t p = nodes[i].parent; p != kNoNode; p = nodes[p].parent) ++count[p];
  };
  for (uint32_t i = 0; i < nodes.size(); ++i)
    if (nodes[i].level == blockLevel) countUp(i, total);
  for (uint32_t b : blocks) countUp(b, given);
  std::vector<uint8_t> out(nodes.size(), 0);
  for (size_t i = 0; i < nodes.size(); ++i)
    out[i] = nodes[i].level < blockLevel && total[i] > 0 && given[i] == total[i];
  return out;
}

std::vector<uint32_t> TilePyramid::frontierOf(const std::vector<NodeRecord>& nodes,
                                              const std::vector<uint8_t>& builds,
                                              const std::vector<uint32_t>& blocks) {
  auto leaves = [&](uint32_t i) {
    const uint32_t p = nodes[i].parent;
    return p == kNoNode || !builds[p];
  };
  std::vector<uint32_t> out;
  for (uint32_t b : blocks)
    if (leaves(b)) out.push_back(b);
  for (uint32_t i = 0; i < nodes.size(); ++i)
    if (builds[i] && leaves(i)) out.push_back(i);
  std::sort(out.begin(), out.end());
  return out;
}

std::vector<uint8_t> TilePyramid::ancestorsOf(const std::vector<NodeRecord>& nodes,
                                              const std::vector<uint32_t>& frontier) {
  std::vector<uint8_t> out(nodes.size(), 0);
  for (uint32_t f : frontier)
    for (uint32_t p = nodes[f].parent; p != kNoNode && !out[p]; p = nodes[p].parent) out[p] = 1;
  return out;
}

}  // namespace terralod
