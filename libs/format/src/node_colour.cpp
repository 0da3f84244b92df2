#include "terralod/format/node_colour.h"

#include <string>

#include "terralod/format/texture_decode.h"

namespace terralod {

Result<NodeColour> readNodeColour(const TilesetReader& tileset, uint32_t node) {
  const TextureSource source = textureSourceOf(tileset.nodes(), node);
  if (source.owner == kNoNode) return NodeColour{};
  const std::string subject = tileset.name() + " chunk " + std::to_string(source.owner);
  auto chunk = tileset.readChunkData(source.owner);
  if (!chunk) return chunk.error();
  const TextureLayer* color =
      chunk->texture ? chunk->texture->find(TextureLayerKind::kColor) : nullptr;
  if (!color) return NodeColour{};
  if (color->encoding != TextureEncoding::kBc1)
    return makeError(subject, "colour texture is not BC1");
  NodeColour whole{decodeBc1Rgb(color->mips[0], color->size), color->size};
  if (whole.rgb.empty()) return makeError(subject, "colour texture cannot be decoded");
  if (source.depth == 0) return whole;
  // The node's square: (size - 1) / 2^depth intervals, the shared border texels included.
  const uint32_t intervals = (whole.size - 1) >> source.depth;
  if (intervals == 0 || intervals << source.depth != whole.size - 1)
    return makeError(subject, "colour texture of " + std::to_string(whole.size) +
                                  " texels cannot be shared by its descendants");
  NodeColour part{{}, intervals + 1};
  part.rgb.reserve(size_t(part.size) * part.size * 3);
  for (uint32_t y = 0; y < part.size; ++y) {
    const size_t row = size_t(source.row) * intervals + y;
    const uint8_t* from = &whole.rgb[(row * whole.size + size_t(source.column) * intervals) * 3];
    part.rgb.insert(part.rgb.end(), from, from + size_t(part.size) * 3);
  }
  return part;
}

}  // namespace terralod
