#include "terralod/build/pass_one_textures.h"

#include <algorithm>

#include "terralod/build/chunk_pass.h"
#include "terralod/build/surface_texels.h"

namespace terralod {
namespace {

// A block's margined window as the texture pass reads it: that exact window and nothing else.
class OneWindow final : public HeightWindows {
 public:
  OneWindow(int32_t x0, int32_t y0, int32_t side, const float* values)
      : mX0(x0), mY0(y0), mSide(side), mValues(values) {}
  Status read(int32_t x0, int32_t y0, int32_t w, int32_t h, float* out, unsigned) override {
    if (x0 != mX0 || y0 != mY0 || w != mSide || h != mSide)
      return Error{"internal error: the texture pass read outside its block's window"};
    std::copy_n(mValues, size_t(w) * size_t(h), out);
    return {};
  }

 private:
  int32_t mX0, mY0, mSide;
  const float* mValues;
};

}  // namespace

PassOneTextures::PassOneTextures(const TreeLayout& layout, const TextureBuild& build,
                                 const std::vector<NodeRecord>& nodes, int32_t blockCells,
                                 unsigned threads)
    : mLayout(layout),
      mBlock(std::clamp(blockCells, layout.leafCells, layout.rootCells)),
      mPass(layout, build, nodes, threads),
      mPyramid(mPass, nodes,
               TilePyramid::buildableFrom(nodes, blockLevelOf(layout, mBlock),
                                          blockNodesOf(nodes, blockLevelOf(layout, mBlock)))),
      mBlobs(nodes.size()) {
  const int32_t blocksX = layout.gridX() / mBlock, blocksY = layout.gridY() / mBlock;
  mBlockNodes.assign(size_t(blocksX) * size_t(blocksY), kNoNode);
  for (uint32_t i : blockNodesOf(nodes, blockLevelOf(layout, mBlock)))
    mBlockNodes[size_t(nodes[i].y) * size_t(blocksX) + nodes[i].x] = i;
  mDone.assign(mBlockNodes.size(), 0);
}

PassOneTextures::~PassOneTextures() = default;

Status PassOneTextures::open() {
  return mPass.open();
}

uint64_t PassOneTextures::blockBytes(const TextureBuild& build,
                                     const std::vector<NodeRecord>& nodes) {
  std::vector<uint64_t> perNode(build.plan.size(), 0);
  for (size_t level = 0; level < build.plan.size(); ++level) {
    const TextureLevel& t = build.plan[level];
    if (t.inherited) continue;
    for (uint32_t m = 0; m < mipCount(t.colorSize); ++m)
      perNode[level] += mipBytes(build.colourEncoding(), t.colorSize, m);
    for (uint32_t m = 0; m < mipCount(t.normalSize); ++m)
      perNode[level] += mipBytes(TextureEncoding::kBc5, t.normalSize, m);
  }
  uint64_t bytes = 0;
  for (const NodeRecord& n : nodes)
    if (n.level < perNode.size()) bytes += perNode[n.level];
  return bytes;
}

int32_t PassOneTextures::margin() const {
  return BlockTexels::kMargin;
}

Status PassOneTextures::useBlock(int32_t x0, int32_t y0, int32_t side, const float* heights,
                                 unsigned worker) {
  const int32_t blocksX = mLayout.gridX() / mBlock;
  const size_t b = size_t(y0 / mBlock) * size_t(blocksX) + size_t(x0 / mBlock);
  if (side != mBlock || b >= mBlockNodes.size() || mBlockNodes[b] == kNoNode)
    return Error{"internal error: pass 1 gave the texture pass a block it does not have"};
  if (mDone[b]) return Error{"internal error: pass 1 gave the texture pass a block twice"};
  const uint32_t root = mBlockNodes[b];
  OneWindow window(x0 - margin(), y0 - margin(), side + 1 + 2 * margin(), heights);
  std::vector<std::pair<uint32_t, std::vector<uint8_t>>> blobs;
  auto tiles = mPass.buildBlock(root, window, worker, blobs);
  if (!tiles) return tiles.error();
  for (auto& [node, blob] : blobs) mBlobs[node] = std::move(blob);  // each node once: no race
  mPyramid.add(root, std::move(tiles).value());
  mDone[b] = 1;
  return {};
}

Result<std::vector<std::vector<uint8_t>>> PassOneTextures::take() {
  for (size_t b = 0; b < mBlockNodes.size(); ++b)
    if (mBlockNodes[b] != kNoNode && !mDone[b])
      return Error{"internal error: pass 1 did not give the texture pass every block"};
  for (auto& [node, blob] : mPyramid.takeTextures()) mBlobs[node] = std::move(blob);
  return std::move(mBlobs);
}

}  // namespace terralod
