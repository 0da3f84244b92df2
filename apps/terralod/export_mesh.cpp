#include "export_mesh.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <unordered_map>

#include "terralod/format/chunk_position.h"

namespace terralod::cli {
namespace {

// Below this two heights are the same point: the verifier's floating-point slack. Chunks
// quantise heights against their own zBase, so equal heights can differ in the last bits.
constexpr double kHeightTolerance = 1e-6;
constexpr uint32_t kUnmapped = std::numeric_limits<uint32_t>::max();

struct WeldedVertex {
  uint32_t index;
  double z;
};

uint64_t gridKey(int64_t x, int64_t y) {
  return (uint64_t(x) << 32) | uint64_t(uint32_t(y));
}

}  // namespace

Result<LevelSurface> gatherLevelSurface(const TilesetReader& tileset, uint32_t level,
                                        Progress& progress) {
  const TilesetHeader& header = tileset.header();
  assert(level < header.levelCount);
  const int64_t side = header.chunkCells(int32_t(level));
  LevelSurface surface;
  for (const NodeRecord& n : tileset.nodes()) surface.chunks += n.level == level;

  // Only chunk-border vertices can be shared with another chunk, so only they stay in the
  // level-wide map; the rest are welded per chunk (a chunk split into parts repeats the
  // vertices along the cut) and forgotten, which keeps memory proportional to the borders.
  std::unordered_map<uint64_t, WeldedVertex> border, interior;
  std::vector<uint32_t> remap;
  progress.begin("reading chunks", surface.chunks);
  for (uint32_t i = 0; i < tileset.nodes().size(); ++i) {
    const NodeRecord& node = tileset.nodes()[i];
    if (node.level != level) continue;
    auto chunk = tileset.readChunk(i);
    if (!chunk) return chunk.error();
    const ChunkGeometry& geometry = *chunk;
    const auto [x0, y0] = chunkCellOrigin(header, node);
    interior.clear();
    for (const ChunkPart& part : geometry.parts) {
      remap.assign(part.vertices.size(), kUnmapped);
      for (uint32_t k = 0; k < part.surfaceIndexCount; ++k) {
        const uint32_t local = part.indices[k];
        if (remap[local] == kUnmapped) {
          const ChunkVertex& v = part.vertices[local];
          const bool onBorder = v.x == 0 || v.y == 0 || v.x == side || v.y == side;
          const auto p = chunkWorldPosition(header, node, geometry, v);
          auto [it, fresh] =
              (onBorder ? border : interior)
                  .try_emplace(gridKey(x0 + v.x, y0 + v.y),
                               WeldedVertex{uint32_t(surface.positions.size()), p[2]});
          if (fresh) {
            if (surface.positions.size() == kUnmapped)
              return makeError(tileset.name(), "level " + std::to_string(level) +
                                                   " has too many vertices for 32-bit indices");
            surface.positions.push_back({float(p[0]), float(p[1]), float(p[2])});
          } else {
            const double difference = std::fabs(p[2] - it->second.z);
            ++surface.weldedVertices;
            surface.maxHeightDifference = std::max(surface.maxHeightDifference, difference);
            surface.heightMismatches += difference > kHeightTolerance;
          }
          remap[local] = it->second.index;
        }
        surface.indices.push_back(remap[local]);
      }
    }
    progress.advance();
  }
  progress.end();
  return surface;
}

}  // namespace terralod::cli
