#include "local_chunk.h"

#include <stb_image_write.h>

#include <cmath>
#include <set>
#include <unordered_map>

#include "terralod/core/srgb.h"
#include "terralod/format/chunk_position.h"
#include "terralod/format/node_colour.h"
#include "terralod/format/vipm_chunk_codec.h"

namespace terralod::tiles3d {
namespace {

// The colour a chunk draws (its own tile, or its square of an ancestor's) as JPEG (rows as
// stored: the southern first, which glTF's v = 0 addresses), or empty when it has none.
Result<std::vector<uint8_t>> colourJpeg(NodeColours& colours, uint32_t node,
                                        const std::string& subject, uint32_t& size) {
  auto colour = colours.read(node);
  if (!colour) return colour.error();
  if (colour->rgb.empty()) return std::vector<uint8_t>{};
  size = colour->size;
  std::vector<uint8_t> jpeg;
  const auto sink = [](void* context, void* data, int n) {
    auto* out = static_cast<std::vector<uint8_t>*>(context);
    const auto* p = static_cast<const uint8_t*>(data);
    out->insert(out->end(), p, p + n);
  };
  if (!stbi_write_jpg_to_func(sink, &jpeg, int(size), int(size), 3, colour->rgb.data(), 90))
    return makeError(subject, "colour texture cannot be encoded as JPEG");
  return jpeg;
}

}  // namespace

Result<LocalChunk> staticLocalChunk(const TilesetReader& tileset, NodeColours& colours,
                                    uint32_t node) {
  const TilesetHeader& h = tileset.header();
  const NodeRecord& record = tileset.nodes()[node];
  const std::string subject = tileset.name() + " chunk " + std::to_string(node);
  auto chunk = tileset.readChunkData(node);
  if (!chunk) return chunk.error();
  LocalChunk out;
  for (const ChunkPart& part : chunk->geometry.parts) {
    const uint32_t base = uint32_t(out.positions.size());
    for (const ChunkVertex& v : part.vertices)
      out.positions.push_back(chunkWorldPosition(h, record, chunk->geometry, v));
    for (size_t k = 0; k < part.indices.size(); ++k) {
      out.indices.push_back(base + part.indices[k]);
      if (k < part.surfaceIndexCount) out.surface.push_back(base + part.indices[k]);
    }
  }
  // Texture coordinates: the tile's texels are edge-aligned over the chunk's square.
  uint32_t size = 0;
  auto jpeg = colourJpeg(colours, node, subject, size);
  if (!jpeg) return jpeg.error();
  if (!jpeg->empty()) {
    out.image = std::move(jpeg).value();
    const auto [ox, oy] = chunkCellOrigin(h, record);
    const double side = h.chunkCells(record.level);
    const double texelsPerMetreX = double(size - 1) / (side * h.spacingX);
    const double texelsPerMetreY = double(size - 1) / (side * h.spacingY);
    for (const auto& p : out.positions)
      out.texcoords.push_back(
          {float(((p[0] - double(ox) * h.spacingX) * texelsPerMetreX + 0.5) / size),
           float(((p[1] - double(oy) * h.spacingY) * texelsPerMetreY + 0.5) / size)});
  }
  return out;
}

Result<LocalChunk> vipmLocalChunk(const TilesetReader& tileset, uint32_t node) {
  const TilesetHeader& h = tileset.header();
  const NodeRecord& record = tileset.nodes()[node];
  const std::string subject = tileset.name() + " chunk " + std::to_string(node);
  auto bytes = tileset.readNode(node);
  if (!bytes) return bytes.error();
  auto data = decodeVipmChunk(bytes->mesh(), subject);
  if (!data) return data.error();
  // The materials' colours, linear (glTF's vertex colours are).
  std::vector<std::array<uint8_t, 3>> palette;
  for (const TilesetMaterial& m : tileset.metadata().materials) {
    std::array<uint8_t, 3> linear{};
    for (size_t k = 0; k < 3; ++k)
      linear[k] = uint8_t(std::lround(srgbToLinear(m.color[k]) * 255.0f));
    palette.push_back(linear);
  }
  LocalChunk out;
  const auto [ox, oy] = chunkCellOrigin(h, record);
  for (uint32_t v = 0; v < data->vertexCount(); ++v) {
    const int64_t x = ox + int64_t(data->points[v] % data->width);
    const int64_t y = oy + int64_t(data->points[v] / data->width);
    out.positions.push_back({double(x) * h.spacingX, double(y) * h.spacingY,
                             data->zBase + double(data->heights[v]) * data->zStep});
    const uint8_t m = data->materials[v];
    if (m >= palette.size())
      return makeError(subject, "names material " + std::to_string(m) + " the metadata lacks");
    out.colors.push_back(palette[m]);
  }
  out.indices.assign(data->indices.begin(), data->indices.end());
  out.surface = out.indices;
  const double depth =
      record.maxSkirtDepth > 0 ? double(record.maxSkirtDepth) : double(h.levelError[record.level]);
  addBorderFlanges(out, depth);
  return out;
}

void addBorderFlanges(LocalChunk& chunk, double depth) {
  // Each directed edge of a triangle; a border edge's reverse belongs to no triangle.
  std::set<std::pair<uint32_t, uint32_t>> edges;
  for (size_t t = 0; t + 2 < chunk.surface.size(); t += 3)
    for (int k = 0; k < 3; ++k)
      edges.insert({chunk.surface[t + k], chunk.surface[t + (k + 1) % 3]});
  std::unordered_map<uint32_t, uint32_t> below;  // a border vertex -> its copy `depth` below
  const auto bottom = [&](uint32_t v) {
    auto [it, fresh] = below.try_emplace(v, uint32_t(chunk.positions.size()));
    if (fresh) {
      const auto p = chunk.positions[v];
      chunk.positions.push_back({p[0], p[1], p[2] - depth});
      if (!chunk.colors.empty()) chunk.colors.push_back(chunk.colors[v]);
      if (!chunk.texcoords.empty()) chunk.texcoords.push_back(chunk.texcoords[v]);
    }
    return it->second;
  };
  for (const auto& edge : edges) {
    if (edges.count({edge.second, edge.first})) continue;
    // The surface is counter-clockwise from above, so (a, b) runs with the chunk on its left:
    // (a, a', b) and (b, a', b') face out.
    const auto [a, b] = edge;
    const uint32_t a2 = bottom(a), b2 = bottom(b);
    chunk.indices.insert(chunk.indices.end(), {a, a2, b, b, a2, b2});
  }
}

}  // namespace terralod::tiles3d
