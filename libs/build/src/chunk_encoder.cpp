#include "terralod/build/chunk_encoder.h"

#include "terralod/format/rtin_chunk_codec.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <limits>

namespace terralod {
namespace {

constexpr size_t kPartVertexLimit = 65535;

// The chunk's height scale and skirt steps in `g`, and its vertices quantised on them: the
// surface's (payload versions 2 and 3) or all of them (version 1).
Result<std::vector<ChunkVertex>> quantizeVertices(const ChunkMesh& mesh, const ErrorBudget& budget,
                                                  ChunkPayloadVersion payload, ChunkGeometry& g) {
  const bool derived = payload != ChunkPayloadVersion::kStoredSkirts;
  auto rangeError = [&] {
    return Error{"internal error: chunk " + std::to_string(mesh.level) + "/" +
                 std::to_string(mesh.ix) + "/" + std::to_string(mesh.iy) +
                 " exceeds its 16-bit height range"};
  };
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
  return vertices;
}

// Groups the quantised vertices and the mesh's triangles into the geometry's parts.
void splitIntoParts(const ChunkMesh& mesh, std::vector<ChunkVertex> vertices,
                    ChunkPayloadVersion payload, ChunkGeometry& g) {
  // The skirts as stored (version 1), or what a reader will derive (versions 2 and 3): the
  // parts leave room for them either way.
  const bool derived = payload != ChunkPayloadVersion::kStoredSkirts;
  const std::vector<uint32_t> noSkirt;
  const std::vector<uint32_t>& skirt = derived ? noSkirt : mesh.skirtIndices;
  if (payload != ChunkPayloadVersion::kRtinCoded && mesh.vertices.size() <= kPartVertexLimit) {
    ChunkPart& part = g.parts.emplace_back();
    part.vertices = std::move(vertices);
    part.indices = mesh.surfaceIndices;
    part.surfaceIndexCount = static_cast<uint32_t>(part.indices.size());
    part.indices.insert(part.indices.end(), skirt.begin(), skirt.end());
  } else {
    // Payload version 3's reader splits the surface by the same rule.
    g.parts =
        splitChunkParts(vertices, mesh.surfaceIndices, skirt,
                        derived ? g.skirtSteps : std::array<uint16_t, 4>{}, uint16_t(mesh.side));
  }
  // No vertex cache optimisation: the mesher emits triangles along a Sierpinski curve with
  // vertices in first-use order, which the index codec compresses about as well as a
  // cache-optimised order (docs/benchmarks.md) at no cost.
}

}  // namespace

Result<ChunkGeometry> quantizeChunk(const ChunkMesh& mesh, const ErrorBudget& budget,
                                    ChunkPayloadVersion payload) {
  ChunkGeometry g;
  auto vertices = quantizeVertices(mesh, budget, payload, g);
  if (!vertices) return vertices.error();
  splitIntoParts(mesh, std::move(*vertices), payload, g);
  return g;
}

Result<EncodedChunk> encodeChunkMesh(const ChunkMesh& mesh, const ErrorBudget& budget,
                                     ChunkPayloadVersion payload, int compressionLevel) {
  EncodedChunk out;
  auto vertices = quantizeVertices(mesh, budget, payload, out.geometry);
  if (!vertices) return vertices.error();
  if (payload == ChunkPayloadVersion::kRtinCoded && !mesh.rtinDecisions.empty()) {
    const ChunkGeometry& g = out.geometry;
    auto blob = encodeRtinChunk({std::countr_zero(uint32_t(mesh.side)),
                                 squareHasRisingDiagonal(mesh.x0, mesh.y0, mesh.side),
                                 uint16_t(mesh.dataX), uint16_t(mesh.dataY), mesh.level > 0,
                                 g.zStep, int32_t(std::lround(g.zBase / g.zStep)), g.skirtSteps,
                                 mesh.rtinDecisions, *vertices, mesh.surfaceIndices});
    if (blob) {
      out.blob = std::move(*blob);
      out.payload = ChunkPayloadVersion::kRtinCoded;
    }
  }
  // Greedy chunks, and any the walk would not reproduce, as payload version 2.
  if (out.blob.empty()) {
    splitIntoParts(mesh, std::move(*vertices), payload, out.geometry);
    out.payload =
        payload == ChunkPayloadVersion::kRtinCoded ? ChunkPayloadVersion::kDerivedSkirts : payload;
    out.blob = encodeChunk(out.geometry, compressionLevel, out.payload);
  }
  return out;
}

}  // namespace terralod
