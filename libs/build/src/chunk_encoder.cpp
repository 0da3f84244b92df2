#include "terralod/build/chunk_encoder.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <unordered_map>

namespace terralod {
namespace {

constexpr size_t kPartVertexLimit = 65535;

// Groups triangles into parts of at most kPartVertexLimit vertices by splitting the chunk's
// square into quadrants (by triangle centroid) until each group fits.
void splitIntoParts(const ChunkMesh& mesh, const std::vector<ChunkVertex>& vertices,
                    std::vector<uint32_t> surface, std::vector<uint32_t> skirt, double x0,
                    double y0, double side, std::vector<ChunkPart>& parts) {
  std::unordered_map<uint32_t, uint32_t> remap;
  for (uint32_t i : surface) remap.try_emplace(i, 0);
  for (uint32_t i : skirt) remap.try_emplace(i, 0);
  if (remap.size() <= kPartVertexLimit || side <= 1) {
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
    splitIntoParts(mesh, vertices, std::move(qs[q]), std::move(qk[q]), x0 + (q & 1) * half,
                   y0 + (q >> 1) * half, half, parts);
}

}  // namespace

Result<ChunkGeometry> quantizeChunk(const ChunkMesh& mesh, const ErrorBudget& budget) {
  ChunkGeometry g;
  g.zStep = budget.zStep[mesh.level];
  double zMin = std::numeric_limits<double>::infinity();
  for (const MeshVertex& v : mesh.vertices) zMin = std::min(zMin, v.z);
  // Heights are rounded on one grid per level, the multiples of zStep, not relative to each
  // chunk's base: neighbours then store a shared border vertex at exactly the same height even
  // when it lies halfway between two steps.
  const double baseSteps = std::floor(zMin / g.zStep);
  g.zBase = baseSteps * g.zStep;

  std::vector<ChunkVertex> vertices(mesh.vertices.size());
  for (size_t i = 0; i < mesh.vertices.size(); ++i) {
    const MeshVertex& v = mesh.vertices[i];
    const double zq = std::round(v.z / g.zStep) - baseSteps;
    // The target is rounded on the same grid, so a vertex whose target is its own height gets
    // a delta of exactly 0.
    const double dq = std::round(v.morphTarget / g.zStep) - baseSteps - zq;
    if (zq < 0 || zq > 65535 || dq < -32768 || dq > 32767)
      return Error{"internal error: chunk " + std::to_string(mesh.level) + "/" +
                   std::to_string(mesh.ix) + "/" + std::to_string(mesh.iy) +
                   " exceeds its 16-bit height range"};
    vertices[i] = {static_cast<uint16_t>(v.x - mesh.x0), static_cast<uint16_t>(v.y - mesh.y0),
                   static_cast<uint16_t>(zq), static_cast<int16_t>(dq)};
  }
  if (vertices.size() <= kPartVertexLimit) {
    ChunkPart& part = g.parts.emplace_back();
    part.vertices = std::move(vertices);
    part.indices = mesh.surfaceIndices;
    part.surfaceIndexCount = static_cast<uint32_t>(part.indices.size());
    part.indices.insert(part.indices.end(), mesh.skirtIndices.begin(), mesh.skirtIndices.end());
  } else {
    splitIntoParts(mesh, vertices, mesh.surfaceIndices, mesh.skirtIndices, mesh.x0, mesh.y0,
                   mesh.side, g.parts);
  }
  // No vertex cache optimisation: the mesher emits triangles along a Sierpinski curve with
  // vertices in first-use order, which the index codec compresses about as well as a
  // cache-optimised order (docs/benchmarks.md) at no cost.
  return g;
}

}  // namespace terralod
