#include "terralod/build/texture_pass.h"

#include <bit>
#include <unordered_map>

#include "terralod/build/texture_encoder.h"
#include "terralod/raster/image_drape.h"

namespace terralod {

TexturePass::TexturePass(const TreeLayout& layout, const TextureBuild& build,
                         const std::vector<NodeRecord>& nodes, unsigned threads)
    : mLayout(layout), mBuild(build), mNodes(nodes), mImages(threads), mTexels(threads) {
  for (auto& t : mTexels) t = std::make_unique<BlockTexels>(build.surface);
}

TexturePass::~TexturePass() = default;

Status TexturePass::open() {
  if (!mBuild.image) return {};
  for (auto& image : mImages) {
    auto again = mBuild.image->reopen();
    if (!again) return again.error();
    image = std::move(again).value();
  }
  return {};
}

ChunkTiles TexturePass::fromChildren(uint32_t node,
                                     const std::array<const ChunkTiles*, 4>& children) const {
  std::array<const TexelTile*, 4> color{}, normal{};
  for (size_t q = 0; q < 4; ++q)
    if (children[q]) {
      color[q] = &children[q]->color;
      normal[q] = &children[q]->normal;
    }
  const TextureLevel& plan = mBuild.plan[mNodes[node].level];
  ChunkTiles t;
  t.color = resampleTile(mosaicTiles(color), plan.colorSize);
  t.normal = resampleTile(mosaicTiles(normal), plan.normalSize);
  const uint32_t childColor = color[0] ? color[0]->size : 0,
                 childNormal = normal[0] ? normal[0]->size : 0;
  for (size_t q = 0; q < 4; ++q)
    if (children[q]) {
      t.childColor[q] = &children[q]->colorLevel0;
      t.childNormal[q] = &children[q]->normalLevel0;
    }
  if (childColor && 2 * childColor - 1 == plan.colorSize) t.childSize[0] = childColor;
  if (childNormal && 2 * childNormal - 1 == plan.normalSize) t.childSize[1] = childNormal;
  return t;
}

std::vector<uint8_t> TexturePass::encode(uint32_t node, ChunkTiles& tiles) const {
  const TextureLevel& plan = mBuild.plan[mNodes[node].level];
  // A parent that is its children side by side reuses their encoded blocks for mip 0.
  std::vector<uint8_t> color0, normal0;
  if (tiles.childSize[0])
    color0 = mosaicBlocks(tiles.childColor, tiles.childSize[0], TextureEncoding::kBc1);
  if (tiles.childSize[1])
    normal0 = mosaicBlocks(tiles.childNormal, tiles.childSize[1], TextureEncoding::kBc5);
  ChunkTexture texture;
  texture.layers.push_back(encodeColorLayer(tiles.color, plan.colorFlags, std::move(color0)));
  texture.layers.push_back(encodeNormalLayer(tiles.normal, plan.normalFlags, std::move(normal0)));
  tiles.colorLevel0 = texture.layers[0].mips[0];
  tiles.normalLevel0 = texture.layers[1].mips[0];
  tiles.childColor = {};
  tiles.childNormal = {};
  return encodeTexture(texture);
}

Result<ChunkTiles> TexturePass::buildBlock(
    uint32_t root, HeightWindows& heights, unsigned worker,
    std::vector<std::pair<uint32_t, std::vector<uint8_t>>>& blobs) {
  const NodeRecord& r = mNodes[root];
  const int32_t cells = mLayout.chunkCells(r.level);
  BlockTexels& texels = *mTexels[worker];
  if (Status s = texels.load(heights, worker, mImages[worker].get(), int32_t(r.x) * cells,
                             int32_t(r.y) * cells, cells);
      !s)
    return s.error();
  // The subtree breadth-first, then built from the leaves up.
  std::vector<uint32_t> order{root};
  for (size_t i = 0; i < order.size(); ++i) {
    const NodeRecord& n = mNodes[order[i]];
    for (uint32_t c = 0; c < uint32_t(std::popcount(unsigned(n.childMask))); ++c)
      order.push_back(n.firstChild + c);
  }
  std::unordered_map<uint32_t, ChunkTiles> tiles;
  for (size_t k = order.size(); k-- > 0;) {
    const uint32_t i = order[k];
    const NodeRecord& n = mNodes[i];
    ChunkTiles t;
    if (n.childMask == 0) {
      const int32_t c = mLayout.chunkCells(n.level);
      const int32_t x0 = int32_t(n.x) * c, y0 = int32_t(n.y) * c;
      const TextureLevel& plan = mBuild.plan[n.level];
      t.color = resampleTile(texels.colors(x0, y0, c), plan.colorSize);
      t.normal = resampleTile(texels.normals(x0, y0, c), plan.normalSize);
    } else {
      std::array<const ChunkTiles*, 4> children{};
      uint32_t c = n.firstChild;
      for (int q = 0; q < 4; ++q)
        if (n.childMask & (1u << q)) children[size_t(q)] = &tiles.at(c++);
      t = fromChildren(i, children);
    }
    blobs.emplace_back(i, encode(i, t));
    for (uint32_t j = 0; j < uint32_t(std::popcount(unsigned(n.childMask))); ++j)
      tiles.erase(n.firstChild + j);
    tiles.emplace(i, std::move(t));
  }
  return std::move(tiles.at(root));
}

}  // namespace terralod
