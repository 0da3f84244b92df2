#include "terralod/format/node_colour.h"

#include <algorithm>
#include <string>

#include "terralod/format/texture_decode.h"

namespace terralod {
namespace {

// Texel intervals a side of a node's square in its owner's tile of `size` texels: the square
// is 1 / 2^depth of the owner's; 0 when the tile cannot be divided so.
uint32_t sharedIntervals(uint32_t size, uint32_t depth) {
  const uint32_t intervals = (size - 1) >> depth;
  return intervals > 0 && intervals << depth == size - 1 ? intervals : 0;
}

Error undividable(const TilesetReader& tileset, uint32_t owner, uint32_t size) {
  return makeError(
      tileset.name() + " chunk " + std::to_string(owner),
      "colour texture of " + std::to_string(size) + " texels cannot be shared by its descendants");
}

}  // namespace

Result<std::shared_ptr<const NodeColour>> NodeColours::owned(uint32_t owner) {
  {
    std::lock_guard lock(mMutex);
    for (const auto& [node, colour] : mKept)
      if (node == owner) return colour;
  }
  const std::string subject = mTileset.name() + " chunk " + std::to_string(owner);
  auto chunk = mTileset.readChunkData(owner);
  if (!chunk) return chunk.error();
  const TextureLayer* color =
      chunk->texture ? chunk->texture->find(TextureLayerKind::kColor) : nullptr;
  auto decoded = std::make_shared<NodeColour>();
  if (color) {
    if (color->encoding != TextureEncoding::kBc1)
      return makeError(subject, "colour texture is not BC1");
    decoded->rgb = decodeBc1Rgb(color->mips[0], color->size);
    decoded->size = color->size;
    if (decoded->rgb.empty()) return makeError(subject, "colour texture cannot be decoded");
  }
  std::lock_guard lock(mMutex);
  if (mKept.size() == kKept) mKept.erase(mKept.begin());
  mKept.emplace_back(owner, decoded);
  return std::shared_ptr<const NodeColour>(std::move(decoded));
}

Result<NodeColour> NodeColours::read(uint32_t node) {
  const TextureSource source = textureSourceOf(mTileset.nodes(), node);
  if (source.owner == kNoNode) return NodeColour{};
  auto whole = owned(source.owner);
  if (!whole) return whole.error();
  const NodeColour& w = **whole;
  if (source.depth == 0 || w.rgb.empty()) return w;
  // The node's square, the shared border texels included.
  const uint32_t intervals = sharedIntervals(w.size, source.depth);
  if (intervals == 0) return undividable(mTileset, source.owner, w.size);
  NodeColour part{{}, intervals + 1};
  part.rgb.reserve(size_t(part.size) * part.size * 3);
  for (uint32_t y = 0; y < part.size; ++y) {
    const size_t row = size_t(source.row) * intervals + y;
    const uint8_t* from = &w.rgb[(row * w.size + size_t(source.column) * intervals) * 3];
    part.rgb.insert(part.rgb.end(), from, from + size_t(part.size) * 3);
  }
  return part;
}

Result<NodeColour> readNodeColour(const TilesetReader& tileset, uint32_t node) {
  return NodeColours(tileset).read(node);
}

Result<uint32_t> nodeColourSize(const TilesetReader& tileset, uint32_t node) {
  const TextureSource source = textureSourceOf(tileset.nodes(), node);
  if (source.owner == kNoNode) return 0u;
  auto chunk = tileset.readChunkData(source.owner);
  if (!chunk) return chunk.error();
  const TextureLayer* color =
      chunk->texture ? chunk->texture->find(TextureLayerKind::kColor) : nullptr;
  if (!color) return 0u;
  if (source.depth == 0) return color->size;
  const uint32_t intervals = sharedIntervals(color->size, source.depth);
  if (intervals == 0) return undividable(tileset, source.owner, color->size);
  return intervals + 1;
}

}  // namespace terralod
