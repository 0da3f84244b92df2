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

namespace {

// Every level of a tile computed from level 0 down, and encoded.
LayerLevels levelsOf(TexelTile level0, TextureEncoding encoding) {
  LayerLevels l;
  const uint32_t size = level0.size, mips = mipCount(size);
  l.levels.push_back(std::move(level0));
  for (uint32_t m = 1; m < mips; ++m)
    l.levels.push_back(nextMip(l.levels.back(), mipSize(size, m)));
  for (const TexelTile& t : l.levels) l.blocks.push_back(encodeLevel(t, encoding));
  return l;
}

// A parent's layer of `size` texels from its children's layers (null: no such child).
LayerLevels parentLevels(const std::array<const LayerLevels*, 4>& children, uint32_t size,
                         TextureEncoding encoding) {
  const LayerLevels* any = nullptr;
  bool all = true;
  for (const LayerLevels* c : children) {
    if (c) any = c;
    all = all && c;
  }
  auto childLevel = [&](uint32_t m) {
    std::array<const TexelTile*, 4> tiles{};
    for (size_t q = 0; q < 4; ++q)
      if (children[q]) tiles[q] = &children[q]->levels[m];
    return tiles;
  };
  auto childBlocks = [&](uint32_t m) {
    std::array<const std::vector<uint8_t>*, 4> blocks{};
    for (size_t q = 0; q < 4; ++q)
      if (children[q]) blocks[q] = &children[q]->blocks[m];
    return blocks;
  };
  const uint32_t childSize = any->levels[0].size;
  LayerLevels l;
  l.levels.push_back(resampleTile(mosaicTiles(childLevel(0)), size));
  std::vector<uint8_t> blocks0;
  const bool unresampled = 2 * childSize - 1 == size, halved = childSize == size;
  if (unresampled && all) blocks0 = mosaicBlocks(childBlocks(0), childSize, encoding);
  l.blocks.push_back(blocks0.empty() ? encodeLevel(l.levels[0], encoding) : std::move(blocks0));
  const uint32_t mips = mipCount(size);
  for (uint32_t m = 1; m < mips; ++m) {
    const uint32_t levelSize = mipSize(size, m);
    const uint32_t from = unresampled ? m : halved ? m + 1 : 0;
    const bool side =
        from > 0 && from < any->levels.size() && 2 * any->levels[from].size == levelSize;
    if (!side) {
      l.levels.push_back(nextMip(l.levels.back(), levelSize));
      l.blocks.push_back(encodeLevel(l.levels.back(), encoding));
      continue;
    }
    l.levels.push_back(concatTiles(childLevel(from)));
    std::vector<uint8_t> blocks =
        all ? concatBlocks(childBlocks(from), any->levels[from].size, encoding)
            : std::vector<uint8_t>{};
    l.blocks.push_back(blocks.empty() ? encodeLevel(l.levels.back(), encoding) : std::move(blocks));
  }
  return l;
}

}  // namespace

ChunkTiles TexturePass::fromChildren(uint32_t node,
                                     const std::array<const ChunkTiles*, 4>& children) const {
  std::array<const LayerLevels*, 4> color{}, normal{};
  for (size_t q = 0; q < 4; ++q)
    if (children[q]) {
      color[q] = &children[q]->color;
      normal[q] = &children[q]->normal;
    }
  const TextureLevel& plan = mBuild.plan[mNodes[node].level];
  return {parentLevels(color, plan.colorSize, TextureEncoding::kBc1),
          parentLevels(normal, plan.normalSize, TextureEncoding::kBc5)};
}

std::vector<uint8_t> TexturePass::encode(uint32_t node, const ChunkTiles& tiles) const {
  const TextureLevel& plan = mBuild.plan[mNodes[node].level];
  auto layer = [](const LayerLevels& l, TextureLayerKind kind, TextureEncoding encoding,
                  uint8_t flags) {
    TextureLayer out;
    out.kind = kind;
    out.encoding = encoding;
    out.flags = flags;
    out.size = l.levels[0].size;
    out.mips = l.blocks;
    return out;
  };
  ChunkTexture texture;
  texture.layers.push_back(
      layer(tiles.color, TextureLayerKind::kColor, TextureEncoding::kBc1, plan.colorFlags));
  texture.layers.push_back(
      layer(tiles.normal, TextureLayerKind::kNormal, TextureEncoding::kBc5, plan.normalFlags));
  return encodeTexture(texture, mBuild.zstdLevel);
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
      t.color =
          levelsOf(resampleTile(texels.colors(x0, y0, c), plan.colorSize), TextureEncoding::kBc1);
      t.normal =
          levelsOf(resampleTile(texels.normals(x0, y0, c), plan.normalSize), TextureEncoding::kBc5);
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
