#include "terralod/build/chunk_encoder.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <unordered_map>

namespace terralod {
namespace {

constexpr size_t kPartVertexLimit = 65535;

// Skirt bottoms a reader derives for these surface triangles of the chunk (payload version 2):
// one per vertex and skirted side, over the edges along that side.
size_t derivedBottoms(const std::vector<ChunkVertex>& vertices,
                      const std::vector<uint32_t>& surface, const ChunkMesh& mesh,
                      const std::array<uint16_t, 4>& skirtSteps) {
  ChunkPart part;
  std::unordered_map<uint32_t, uint32_t> local;
  for (uint32_t i : surface) {
    auto [it, fresh] = local.try_emplace(i, uint32_t(part.vertices.size()));
    if (fresh) part.vertices.push_back(vertices[i]);
    part.indices.push_back(it->second);
  }
  part.surfaceIndexCount = uint32_t(part.indices.size());
  const auto side = uint16_t(mesh.side);
  // The extents a reader finds: the chunk's side wherever a side has a skirt (its footprint is
  // clipped only along the data's boundary, which has none).
  std::vector<uint64_t> keys;
  for (const SkirtEdge& e : skirtEdges(part, skirtSteps, side, side))
    keys.insert(keys.end(), {uint64_t(e.p) * 4 + e.side, uint64_t(e.q) * 4 + e.side});
  std::sort(keys.begin(), keys.end());
  return size_t(std::unique(keys.begin(), keys.end()) - keys.begin());
}

// Groups triangles into parts of at most kPartVertexLimit vertices by splitting the chunk's
// square into quadrants (by triangle centroid) until each group fits. With derived skirts
// (`skirt` empty) a group's size counts the bottoms a reader will add to it.
void splitIntoParts(const ChunkMesh& mesh, const std::vector<ChunkVertex>& vertices,
                    const std::array<uint16_t, 4>* derivedSteps, std::vector<uint32_t> surface,
                    std::vector<uint32_t> skirt, double x0, double y0, double side,
                    std::vector<ChunkPart>& parts) {
  std::unordered_map<uint32_t, uint32_t> remap;
  for (uint32_t i : surface) remap.try_emplace(i, 0);
  for (uint32_t i : skirt) remap.try_emplace(i, 0);
  const size_t size =
      remap.size() + (derivedSteps ? derivedBottoms(vertices, surface, mesh, *derivedSteps) : 0);
  if (size <= kPartVertexLimit || side <= 1) {
    ChunkPart part;
    std::vector<uint32_t> order;
    order.reserve(remap.size());
    for (auto& [from, to] : remap) order.push_back(from);
    std::sort(order.begin(), order.end());
    for (uint32_t from : order) {
      remap[from] = static_cast<uint32_t>(part.vertices.size());
      part.vertices.push_back(vertices[from]);
    }
    for (uint32_t i : surface) part.indices.push_back(remap[i]);
    part.surfaceIndexCount = static_cast<uint32_t>(part.indices.size());
    for (uint32_t i : skirt) part.indices.push_back(remap[i]);
    if (!part.indices.empty()) parts.push_back(std::move(part));
    return;
  }
  const double half = side / 2;
  std::vector<uint32_t> qs[4], qk[4];
  auto quadrant = [&](const uint32_t* tri) {
    double cx = 0, cy = 0;
    for (int k = 0; k < 3; ++k) cx += mesh.vertices[tri[k]].x, cy += mesh.vertices[tri[k]].y;
    return (cx / 3 >= x0 + half ? 1 : 0) + (cy / 3 >= y0 + half ? 2 : 0);
  };
  for (size_t t = 0; t < surface.size(); t += 3) {
    auto& q = qs[quadrant(&surface[t])];
    q.insert(q.end(), surface.begin() + t, surface.begin() + t + 3);
  }
  for (size_t t = 0; t < skirt.size(); t += 3) {
    auto& q = qk[quadrant(&skirt[t])];
    q.insert(q.end(), skirt.begin() + t, skirt.begin() + t + 3);
  }
  for (int q = 0; q < 4; ++q)
    splitIntoParts(mesh, vertices, derivedSteps, std::move(qs[q]), std::move(qk[q]),
                   x0 + (q & 1) * half, y0 + (q >> 1) * half, half, parts);
}

}  // namespace

Result<ChunkGeometry> quantizeChunk(const ChunkMesh& mesh, const ErrorBudget& budget,
                                    ChunkPayloadVersion payload) {
  const bool derived = payload == ChunkPayloadVersion::kDerivedSkirts;
  auto rangeError = [&] {
    return Error{"internal error: chunk " + std::to_string(mesh.level) + "/" +
                 std::to_string(mesh.ix) + "/" + std::to_string(mesh.iy) +
                 " exceeds its 16-bit height range"};
  };
  ChunkGeometry g;
  g.zStep = budget.zStep[mesh.level];
  // Heights are rounded on one grid per level, the multiples of zStep, not relative to each
  // chunk's base: neighbours then store a shared border vertex at exactly the same height even
  // when it lies halfway between two steps.
  double baseSteps = std::numeric_limits<double>::infinity();
  if (!derived) {
    for (const MeshVertex& v : mesh.vertices) baseSteps = std::min(baseSteps, v.z);
    baseSteps = std::floor(baseSteps / g.zStep);
  } else {
    // Derived skirts hang whole steps below their tops' rounded heights: at least the side's
    // depth, and the base low enough that every bottom stays at or above 0.
    for (uint32_t i = 0; i < mesh.surfaceVertexCount; ++i)
      baseSteps = std::min(baseSteps, std::floor(mesh.vertices[i].z / g.zStep));
    for (int side = 0; side < 4; ++side) {
      const double depth = mesh.skirtDepth[size_t(side)];
      if (depth <= 0) continue;
      const double steps = std::ceil(depth / g.zStep);
      if (!(steps <= 65535)) return rangeError();
      g.skirtSteps[size_t(side)] = uint16_t(std::max(1.0, steps));
    }
    for (uint32_t i = 0; i < mesh.surfaceVertexCount; ++i) {
      const MeshVertex& v = mesh.vertices[i];
      const bool onSide[4] = {v.y == mesh.y0, v.x == mesh.x0 + mesh.side,
                              v.y == mesh.y0 + mesh.side, v.x == mesh.x0};
      for (int side = 0; side < 4; ++side)
        if (onSide[side] && g.skirtSteps[size_t(side)] > 0)
          baseSteps = std::min(baseSteps, std::round(v.z / g.zStep) - g.skirtSteps[size_t(side)]);
    }
  }
  // (Payload version 2 stores the base as a whole number of steps, a 32-bit integer.)
  if (derived && !(std::fabs(baseSteps) < 2147483647.0)) return rangeError();
  g.zBase = baseSteps * g.zStep;

  const size_t stored = derived ? mesh.surfaceVertexCount : mesh.vertices.size();
  std::vector<ChunkVertex> vertices(stored);
  for (size_t i = 0; i < stored; ++i) {
    const MeshVertex& v = mesh.vertices[i];
    const double zq = std::round(v.z / g.zStep) - baseSteps;
    // The target is rounded on the same grid, so a vertex whose target is its own height gets
    // a delta of exactly 0.
    const double dq = std::round(v.morphTarget / g.zStep) - baseSteps - zq;
    if (zq < 0 || zq > 65535 || dq < -32768 || dq > 32767) return rangeError();
    vertices[i] = {static_cast<uint16_t>(v.x - mesh.x0), static_cast<uint16_t>(v.y - mesh.y0),
                   static_cast<uint16_t>(zq), static_cast<int16_t>(dq)};
  }
  // The skirts as stored (version 1), or what a reader will derive (version 2): the parts
  // leave room for them either way.
  const std::vector<uint32_t> noSkirt;
  const std::vector<uint32_t>& skirt = derived ? noSkirt : mesh.skirtIndices;
  if (mesh.vertices.size() <= kPartVertexLimit) {
    ChunkPart& part = g.parts.emplace_back();
    part.vertices = std::move(vertices);
    part.indices = mesh.surfaceIndices;
    part.surfaceIndexCount = static_cast<uint32_t>(part.indices.size());
    part.indices.insert(part.indices.end(), skirt.begin(), skirt.end());
  } else {
    splitIntoParts(mesh, vertices, derived ? &g.skirtSteps : nullptr, mesh.surfaceIndices, skirt,
                   mesh.x0, mesh.y0, mesh.side, g.parts);
  }
  // No vertex cache optimisation: the mesher emits triangles along a Sierpinski curve with
  // vertices in first-use order, which the index codec compresses about as well as a
  // cache-optimised order (docs/benchmarks.md) at no cost.
  return g;
}

}  // namespace terralod
