#include "terralod/build/texture_pass.h"

#include <bit>
#include <unordered_map>

#include "terralod/build/mosaic_builder.h"
#include "terralod/build/texture_encoder.h"
#include "terralod/raster/image_drape.h"

namespace terralod {

TexturePass::TexturePass(const TreeLayout& layout, const TextureBuild& build,
                         const std::vector<NodeRecord>& nodes, unsigned threads)
    : mLayout(layout), mBuild(build), mNodes(nodes), mImages(threads), mTexels(threads) {
  for (auto& t : mTexels) t = std::make_unique<BlockTexels>(build.surface);
}

TexturePass::~TexturePass() = default;

PartialTiles::PartialTiles() = default;
PartialTiles::PartialTiles(PartialTiles&&) noexcept = default;
PartialTiles& PartialTiles::operator=(PartialTiles&&) noexcept = default;
PartialTiles::~PartialTiles() = default;

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

// For each of a parent's mip levels (of a layer of `size` texels), the level of its children's
// that it is made of side by side, or 0 where it is made from the parent's level above: their
// mip m where the parent holds them unresampled, their mip m + 1 where it halves them.
std::vector<uint32_t> sideBySideSources(const LayerLevels& child, uint32_t size) {
  const uint32_t childSize = child.levels[0].size;
  const bool unresampled = 2 * childSize - 1 == size, halved = childSize == size;
  std::vector<uint32_t> from(mipCount(size), 0);
  for (uint32_t m = 1; m < from.size(); ++m) {
    const uint32_t f = unresampled ? m : halved ? m + 1 : 0;
    if (f > 0 && f < child.levels.size() && 2 * child.levels[f].size == mipSize(size, m))
      from[m] = f;
  }
  return from;
}

// A parent's layer of `size` texels from its children's layers (null: no such child) and its
// level 0 (MosaicBuilder's, from theirs, which they need not hold any more).
LayerLevels parentLevels(const std::array<const LayerLevels*, 4>& children, uint32_t size,
                         TextureEncoding encoding, TexelTile level0) {
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
  l.levels.push_back(std::move(level0));
  std::vector<uint8_t> blocks0;
  if (2 * childSize - 1 == size && all) blocks0 = mosaicBlocks(childBlocks(0), childSize, encoding);
  l.blocks.push_back(blocks0.empty() ? encodeLevel(l.levels[0], encoding) : std::move(blocks0));
  const std::vector<uint32_t> sources = sideBySideSources(*any, size);
  for (uint32_t m = 1; m < sources.size(); ++m) {
    const uint32_t from = sources[m];
    if (from == 0) {
      l.levels.push_back(nextMip(l.levels.back(), mipSize(size, m)));
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

// Frees what parentLevels will not read of a child's layer (`all`: the parent has four
// children), keeping each level's size.
void keepWhatTheParentReads(LayerLevels& l, uint32_t parentSize, bool all) {
  std::vector<uint8_t> keepLevel(l.levels.size(), 0), keepBlocks(l.blocks.size(), 0);
  keepLevel[0] = 1;
  if (all && 2 * l.levels[0].size - 1 == parentSize) keepBlocks[0] = 1;
  for (uint32_t from : sideBySideSources(l, parentSize))
    if (from > 0) {
      keepLevel[from] = 1;
      if (all) keepBlocks[from] = 1;
    }
  for (size_t i = 0; i < l.levels.size(); ++i)
    if (!keepLevel[i]) std::vector<float>().swap(l.levels[i].values);
  for (size_t i = 0; i < l.blocks.size(); ++i)
    if (!keepBlocks[i]) std::vector<uint8_t>().swap(l.blocks[i]);
}

}  // namespace

ChunkTiles TexturePass::fromChildren(uint32_t node,
                                     const std::array<ChunkTiles*, 4>& children) const {
  PartialTiles partial;
  for (size_t q = 0; q < 4; ++q)
    if (children[q]) {
      startParent(node, partial, *children[q]);
      addChild(partial, q, *children[q]);
    }
  return finishParent(node, partial, children);
}

void TexturePass::startParent(uint32_t node, PartialTiles& partial, const ChunkTiles& child) const {
  if (partial.color) return;
  const NodeRecord& n = mNodes[node];
  std::array<bool, 4> present{};
  for (size_t q = 0; q < 4; ++q) present[q] = n.childMask & (1u << q);
  const TextureLevel& plan = mBuild.plan[n.level];
  auto builder = [&](const LayerLevels& l, uint32_t size) {
    return std::make_unique<MosaicBuilder>(l.levels[0].size, l.levels[0].channels, size, present);
  };
  partial.color = builder(child.color, plan.colorSize);
  partial.normal = builder(child.normal, plan.normalSize);
}

void TexturePass::addChild(PartialTiles& partial, size_t quadrant, ChunkTiles& child) const {
  // Taken: the builder keeps it (an unresampled parent) or is done with it (a resampled one).
  partial.color->add(quadrant, std::move(child.color.levels[0]));
  std::vector<float>().swap(child.color.levels[0].values);
  partial.normal->add(quadrant, std::move(child.normal.levels[0]));
  std::vector<float>().swap(child.normal.levels[0].values);
}

ChunkTiles TexturePass::finishParent(uint32_t node, PartialTiles& partial,
                                     const std::array<ChunkTiles*, 4>& children) const {
  const TextureLevel& plan = mBuild.plan[mNodes[node].level];
  auto layerOf = [&](LayerLevels ChunkTiles::*layer, MosaicBuilder& builder, uint32_t size,
                     TextureEncoding encoding) {
    std::array<const LayerLevels*, 4> from{};
    for (size_t q = 0; q < 4; ++q)
      if (children[q]) from[q] = &(children[q]->*layer);
    LayerLevels made = parentLevels(from, size, encoding, builder.finish());
    for (ChunkTiles* c : children)
      if (c) c->*layer = {};
    return made;
  };
  // One layer at a time, each child's layer released once used: the peak holds the children's
  // normals and the parent's colour, not both layers of all five.
  ChunkTiles out;
  out.color = layerOf(&ChunkTiles::color, *partial.color, plan.colorSize, mBuild.colourEncoding());
  out.normal =
      layerOf(&ChunkTiles::normal, *partial.normal, plan.normalSize, TextureEncoding::kBc5);
  return out;
}

void TexturePass::keepWhatTheParentReads(uint32_t node, ChunkTiles& tiles) const {
  const uint32_t parent = mNodes[node].parent;
  if (parent == kNoNode) return;
  const bool all = std::popcount(unsigned(mNodes[parent].childMask)) == 4;
  const TextureLevel& plan = mBuild.plan[mNodes[parent].level];
  terralod::keepWhatTheParentReads(tiles.color, plan.colorSize, all);
  terralod::keepWhatTheParentReads(tiles.normal, plan.normalSize, all);
}

std::vector<uint8_t> TexturePass::encode(uint32_t node, const ChunkTiles& tiles) const {
  const TextureLevel& plan = mBuild.plan[mNodes[node].level];
  if (plan.inherited) return {};  // the parent's texture holds these texels
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
      layer(tiles.color, mBuild.colourKind, mBuild.colourEncoding(), plan.colorFlags));
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
      t.color = levelsOf(
          resampleTile(mBuild.colourKind == TextureLayerKind::kShade ? texels.shades(x0, y0, c)
                                                                     : texels.colors(x0, y0, c),
                       plan.colorSize),
          mBuild.colourEncoding());
      t.normal =
          levelsOf(resampleTile(texels.normals(x0, y0, c), plan.normalSize), TextureEncoding::kBc5);
    } else {
      std::array<ChunkTiles*, 4> children{};
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
