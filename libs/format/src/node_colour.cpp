#include "terralod/format/node_colour.h"

#include <algorithm>
#include <string>

#include "terralod/core/sample_raster.h"
#include "terralod/format/chunk_position.h"
#include "terralod/format/generated_colour.h"
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

// The chunk's own surface (no morph) at every grid point of its square, (cells + 1)² row-major.
std::vector<float> surfaceHeights(const ChunkGeometry& geometry, int64_t cells) {
  const size_t side = size_t(cells + 1);
  std::vector<float> heights(side * side, float(geometry.zBase));
  for (const ChunkPart& part : geometry.parts)
    for (uint32_t t = 0; t + 2 < part.surfaceIndexCount; t += 3) {
      SampleVertex v[3];
      for (int k = 0; k < 3; ++k) {
        const ChunkVertex& c = part.vertices[part.indices[t + uint32_t(k)]];
        v[k] = {c.x, c.y, chunkVertexHeight(geometry, c)};
      }
      rasterizeTriangle(v[0], v[1], v[2], 0, cells, 0, cells, [&](int64_t x, int64_t y, double z) {
        heights[size_t(y) * side + size_t(x)] = float(z);
      });
    }
  return heights;
}

// The generated colour of a shade layer (format version 6) as the shader makes it
// (generated_colour.h): height from the chunk's surface, slope from its normal layer.
Result<std::vector<uint8_t>> shadedRgb(const TilesetReader& tileset, uint32_t owner,
                                       const ChunkData& chunk, const TextureLayer& shade,
                                       const std::string& subject) {
  const TextureLayer* normal = chunk.texture->find(TextureLayerKind::kNormal);
  if (!normal) return makeError(subject, "shade texture without a normal texture");
  const std::vector<uint8_t> v = decodeBc4R(shade.mips[0], shade.size);
  const std::vector<uint8_t> n = decodeBc5Rg(normal->mips[0], normal->size);
  if (v.empty() || n.empty()) return makeError(subject, "shade texture cannot be decoded");
  const TilesetHeader& header = tileset.header();
  const NodeRecord& node = tileset.nodes()[owner];
  const int64_t cells = header.chunkCells(node.level);
  const auto origin = chunkCellOrigin(header, node);
  const std::vector<float> heights = surfaceHeights(chunk.geometry, cells);
  const TilesetMetadata& m = tileset.metadata();
  const double lastRow = std::max(1.0, double(m.snowLineLastRow));
  const uint32_t size = shade.size;
  auto byte = [](float c) { return uint8_t(std::clamp(c * 255.0f + 0.5f, 0.0f, 255.0f)); };
  std::vector<uint8_t> rgb(size_t(size) * size * 3);
  for (uint32_t j = 0; j < size; ++j)
    for (uint32_t i = 0; i < size; ++i) {
      // Texel (i, j) lies at (i, j) / (size - 1) of the square: its height bilinearly.
      const double fx = double(i) * double(cells) / double(size - 1);
      const double fy = double(j) * double(cells) / double(size - 1);
      const int64_t x0 = std::min<int64_t>(int64_t(fx), cells - 1);
      const int64_t y0 = std::min<int64_t>(int64_t(fy), cells - 1);
      const double tx = fx - double(x0), ty = fy - double(y0);
      auto h = [&](int64_t x, int64_t y) { return double(heights[size_t(y * (cells + 1) + x)]); };
      const double height = (h(x0, y0) * (1 - tx) + h(x0 + 1, y0) * tx) * (1 - ty) +
                            (h(x0, y0 + 1) * (1 - tx) + h(x0 + 1, y0 + 1) * tx) * ty;
      const uint32_t ni = uint32_t(std::lround(double(i) * (normal->size - 1) / (size - 1)));
      const uint32_t nj = uint32_t(std::lround(double(j) * (normal->size - 1) / (size - 1)));
      const float nx = n[(size_t(nj) * normal->size + ni) * 2] / 255.0f * 2 - 1;
      const float ny = n[(size_t(nj) * normal->size + ni) * 2 + 1] / 255.0f * 2 - 1;
      const float nz = std::sqrt(std::max(0.0f, 1.0f - nx * nx - ny * ny));
      const float snow = snowLineAt(m.snowLine, (double(origin[1]) + fy) / lastRow);
      const GroundColor c =
          shadedColour(float(height), 1.0f - nz, snow, v[size_t(j) * size + i] / 255.0f);
      uint8_t* out = &rgb[(size_t(j) * size + i) * 3];
      out[0] = byte(c.r);
      out[1] = byte(c.g);
      out[2] = byte(c.b);
    }
  return rgb;
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
  const TextureLayer* color = chunk->texture ? chunk->texture->colourSource() : nullptr;
  auto decoded = std::make_shared<NodeColour>();
  if (color && color->kind == TextureLayerKind::kShade) {
    auto rgb = shadedRgb(mTileset, owner, *chunk, *color, subject);
    if (!rgb) return rgb.error();
    decoded->rgb = std::move(rgb).value();
    decoded->size = color->size;
  } else if (color) {
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
  const TextureLayer* color = chunk->texture ? chunk->texture->colourSource() : nullptr;
  if (!color) return 0u;
  if (source.depth == 0) return color->size;
  const uint32_t intervals = sharedIntervals(color->size, source.depth);
  if (intervals == 0) return undividable(tileset, source.owner, color->size);
  return intervals + 1;
}

}  // namespace terralod
