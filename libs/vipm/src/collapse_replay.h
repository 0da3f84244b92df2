#pragma once
// Replays a progressive mesh's collapses over its triangle list in O(vertices + triangles):
// per vertex a linked list of the triangle corners that refer to it; collapse j moves vertex
// v = N - 1 - j's corners onto targets[j], and the triangles holding both die. Checks that the
// mesh is consistent as it goes (what decoding a stored mesh relies on); with
// TriangleOrder::kAny the triangles need not be in removal order yet (the builder replays to
// find that order).
//
//   onMove(j, corner)  corner (3 * triangle + k) changes from v to targets[j]
//   onDeath(j, triangle)

#include <cstdint>
#include <string>
#include <vector>

#include "terralod/core/result.h"
#include "terralod/vipm/progressive_mesh.h"

namespace terralod {

enum class TriangleOrder : uint8_t { kByRemoval, kAny };

template <class OnMove, class OnDeath>
Status replayCollapses(const ProgressiveMesh& mesh, OnMove&& onMove, OnDeath&& onDeath,
                       TriangleOrder order = TriangleOrder::kByRemoval) {
  const uint32_t n = mesh.vertexCount();
  const uint32_t triangleCount = uint32_t(mesh.triangles.size());
  constexpr uint32_t kEnd = UINT32_MAX;
  std::vector<uint32_t> head(n, kEnd), next(size_t(triangleCount) * 3, kEnd);
  std::vector<uint16_t> corner(size_t(triangleCount) * 3);
  for (uint32_t t = 0; t < triangleCount; ++t) {
    for (uint32_t k = 0; k < 3; ++k) {
      const uint16_t v = mesh.triangles[t][k];
      if (v >= n) return Error{"triangle refers to a vertex that does not exist"};
      const uint32_t c = 3 * t + k;
      corner[c] = v;
      next[c] = head[v];
      head[v] = c;
    }
  }
  uint32_t alive = triangleCount;
  std::vector<uint8_t> dead(triangleCount, 0);
  for (uint32_t j = 0; j < mesh.collapseCount(); ++j) {
    const uint32_t v = n - 1 - j;
    const uint16_t u = mesh.targets[j];
    if (u >= v) return Error{"collapse " + std::to_string(j) + " moves onto a removed vertex"};
    uint32_t dying = 0;
    uint32_t c = head[v];
    head[v] = kEnd;
    while (c != kEnd) {
      const uint32_t following = next[c];
      const uint32_t t = c / 3;
      if (!dead[t]) {
        const uint32_t base = 3 * t;
        if (corner[base] == u || corner[base + 1] == u || corner[base + 2] == u) {
          dead[t] = 1;
          ++dying;
          onDeath(j, t);
        } else {
          corner[c] = u;
          next[c] = head[u];
          head[u] = c;
          onMove(j, c);
        }
      }
      c = following;
    }
    if (dying < 1 || dying > 2)
      return Error{"collapse " + std::to_string(j) + " removes " + std::to_string(dying) +
                   " triangles"};
    alive -= dying;
    if (order == TriangleOrder::kByRemoval)
      for (uint32_t t = alive; t < alive + dying; ++t)
        if (!dead[t])
          return Error{"triangles are not in removal order at collapse " + std::to_string(j)};
  }
  return {};
}

}  // namespace terralod
