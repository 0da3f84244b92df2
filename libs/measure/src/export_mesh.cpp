#include "terralod/measure/export_mesh.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <unordered_map>

#include "terralod/format/chunk_position.h"

namespace terralod {
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
  finishSurface(header, surface);
  return surface;
}

void finishSurface(const TilesetHeader& header, LevelSurface& surface) {
  surface.normals = angleWeightedNormals(surface.positions, surface.indices);
  surface.extent = {double(header.sourceColumns - 1) * header.spacingX,
                    double(header.sourceRows - 1) * header.spacingY};
  surface.texcoords.reserve(surface.positions.size());
  for (const auto& p : surface.positions) {
    std::array<float, 2> uv;
    for (int c = 0; c < 2; ++c)
      uv[size_t(c)] = float(std::clamp(double(p[size_t(c)]) / surface.extent[size_t(c)], 0.0, 1.0));
    surface.texcoords.push_back(uv);
  }
}

std::vector<std::array<float, 3>> angleWeightedNormals(
    const std::vector<std::array<float, 3>>& positions, const std::vector<uint32_t>& indices) {
  using Vec = std::array<double, 3>;
  const auto sub = [](const std::array<float, 3>& a, const std::array<float, 3>& b) {
    return Vec{double(a[0]) - b[0], double(a[1]) - b[1], double(a[2]) - b[2]};
  };
  const auto dot = [](const Vec& a, const Vec& b) {
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
  };
  const auto cross = [](const Vec& a, const Vec& b) {
    return Vec{a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
  };
  // Sums in float: at most 2π of weight per vertex, so float keeps them to ~1e-7.
  std::vector<std::array<float, 3>> sums(positions.size(), {0.0f, 0.0f, 0.0f});
  for (size_t k = 0; k + 2 < indices.size(); k += 3) {
    const uint32_t corner[3] = {indices[k], indices[k + 1], indices[k + 2]};
    const Vec e[3] = {sub(positions[corner[1]], positions[corner[0]]),
                      sub(positions[corner[2]], positions[corner[1]]),
                      sub(positions[corner[0]], positions[corner[2]])};
    Vec n = cross(e[0], e[1]);
    const double length = std::sqrt(dot(n, n));
    if (!(length > 0)) continue;
    for (double& c : n) c /= length;
    for (int i = 0; i < 3; ++i) {
      // The angle at corner i, between the edges leaving it (toward i + 1 and toward i - 1).
      const Vec& out = e[i];
      const Vec& in = e[(i + 2) % 3];
      const double angle =
          std::atan2(std::sqrt(dot(cross(out, in), cross(out, in))), -dot(out, in));
      for (int c = 0; c < 3; ++c) sums[corner[i]][size_t(c)] += float(angle * n[size_t(c)]);
    }
  }
  for (auto& s : sums) {
    const double length =
        std::sqrt(double(s[0]) * s[0] + double(s[1]) * s[1] + double(s[2]) * s[2]);
    if (length > 0)
      s = {float(s[0] / length), float(s[1] / length), float(s[2] / length)};
    else
      s = {0.0f, 0.0f, 1.0f};
  }
  return sums;
}

}  // namespace terralod
