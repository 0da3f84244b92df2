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

// The chunk's own surface (no morph) under every texel of a `size`-texel tile over its
// `cells`-cell square, row-major. Texel (i, j) lies at (i, j)·cells/(size − 1) cells: in
// coordinates scaled by size − 1 the vertices and the texels are both on integer points, and
// the shared rasteriser gives each texel row's span (never a grid of the whole square, which
// a 32768-cell root would make 4 GB).
std::vector<float> surfaceAtTexels(const ChunkGeometry& geometry, int64_t cells, uint32_t size) {
  const int64_t s = int64_t(size) - 1;
  std::vector<float> out(size_t(size) * size, float(geometry.zBase));
  struct P {
    int64_t x, y;
    double z;
  };
  auto ceilDiv = [](int64_t a, int64_t b) { return a >= 0 ? (a + b - 1) / b : -((-a) / b); };
  auto floorDiv = [](int64_t a, int64_t b) { return a >= 0 ? a / b : -((-a + b - 1) / b); };
  for (const ChunkPart& part : geometry.parts)
    for (uint32_t t = 0; t + 2 < part.surfaceIndexCount; t += 3) {
      P v[3];
      for (int k = 0; k < 3; ++k) {
        const ChunkVertex& c = part.vertices[part.indices[t + uint32_t(k)]];
        v[k] = {int64_t(c.x) * s, int64_t(c.y) * s, chunkVertexHeight(geometry, c)};
      }
      const double area =
          double((v[1].x - v[0].x) * (v[2].y - v[0].y) - (v[1].y - v[0].y) * (v[2].x - v[0].x));
      if (area == 0) continue;
      const int64_t j0 = std::max<int64_t>(0, ceilDiv(std::min({v[0].y, v[1].y, v[2].y}), cells));
      const int64_t j1 = std::min<int64_t>(s, floorDiv(std::max({v[0].y, v[1].y, v[2].y}), cells));
      for (int64_t j = j0; j <= j1; ++j)
        forEachTriangleRow(
            v[0], v[1], v[2], 0, s * cells, j * cells, j * cells,
            [&](int64_t y, int64_t lo, int64_t hi) {
              for (int64_t i = ceilDiv(lo, cells); i <= floorDiv(hi, cells); ++i) {
                const int64_t x = i * cells;
                const double wa =
                    double((v[1].x - x) * (v[2].y - y) - (v[1].y - y) * (v[2].x - x)) / area;
                const double wb =
                    double((v[2].x - x) * (v[0].y - y) - (v[2].y - y) * (v[0].x - x)) / area;
                out[size_t(j) * size + size_t(i)] =
                    float(wa * v[0].z + wb * v[1].z + (1.0 - wa - wb) * v[2].z);
              }
            });
    }
  return out;
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
  const TilesetMetadata& m = tileset.metadata();
  const double lastRow = std::max(1.0, double(m.snowLineLastRow));
  const uint32_t size = shade.size;
  const std::vector<float> heights = surfaceAtTexels(chunk.geometry, cells, size);
  auto byte = [](float c) { return uint8_t(std::clamp(c * 255.0f + 0.5f, 0.0f, 255.0f)); };
  std::vector<uint8_t> rgb(size_t(size) * size * 3);
  for (uint32_t j = 0; j < size; ++j)
    for (uint32_t i = 0; i < size; ++i) {
      const double fy = double(j) * double(cells) / double(size - 1);
      const float height = heights[size_t(j) * size + i];
      const uint32_t ni = uint32_t(std::lround(double(i) * (normal->size - 1) / (size - 1)));
      const uint32_t nj = uint32_t(std::lround(double(j) * (normal->size - 1) / (size - 1)));
      const float nx = n[(size_t(nj) * normal->size + ni) * 2] / 255.0f * 2 - 1;
      const float ny = n[(size_t(nj) * normal->size + ni) * 2 + 1] / 255.0f * 2 - 1;
      const float nz = std::sqrt(std::max(0.0f, 1.0f - nx * nx - ny * ny));
      const float snow = snowLineAt(m.snowLine, (double(origin[1]) + fy) / lastRow);
      const GroundColor c = shadedColour(height, 1.0f - nz, snow, v[size_t(j) * size + i] / 255.0f);
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
