#include "terralod/vipm/progressive_mesh.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <numeric>

#include "collapse_replay.h"

namespace terralod {
namespace {

uint16_t find(std::vector<uint16_t>& rep, uint16_t v) {
  while (rep[v] != v) v = rep[v] = rep[rep[v]];
  return v;
}

}  // namespace

ProgressiveMesh makeProgressiveMesh(const GridPatch& patch, const CollapseOrder& order,
                                    double maxError) {
  const uint32_t n = patch.pointCount();
  const auto& all = order.collapses;
  size_t applied = 0;
  while (applied < all.size() && double(all[applied].error) <= maxError) ++applied;

  ProgressiveMesh mesh;
  mesh.width = patch.width;
  mesh.height = patch.height;
  double quantisation = 0.0;
  for (uint32_t v = 0; v < n; ++v)
    quantisation =
        std::max(quantisation, std::abs(double(patch.heights[v]) - patch.vertexHeight(v)));
  mesh.finestError =
      applied > 0 ? all[applied - 1].error : std::max(float(quantisation), order.startError);

  // Vertex order: never removed (by point id; points of the start's triangles only), then the
  // runtime collapses' vertices, last removed first.
  std::vector<uint8_t> used(n, 0), removed(n, 0);
  for (const auto& tri : order.gridTriangles)
    for (uint16_t v : tri) used[v] = 1;
  for (const Collapse& c : all) removed[c.vertex] = 1;
  for (uint32_t v = 0; v < n; ++v)
    if (used[v] && !removed[v]) mesh.patchIds.push_back(uint16_t(v));
  for (size_t k = all.size(); k-- > applied;) mesh.patchIds.push_back(all[k].vertex);
  std::vector<uint16_t> index(n, UINT16_MAX);
  for (uint32_t i = 0; i < mesh.patchIds.size(); ++i) {
    index[mesh.patchIds[i]] = uint16_t(i);
    mesh.points.push_back(patch.gridPoint(mesh.patchIds[i]));
  }
  for (size_t k = applied; k < all.size(); ++k) {
    mesh.targets.push_back(index[all[k].target]);
    mesh.errors.push_back(all[k].error);
  }

  // The finest level's triangles: the grid's, through the applied collapses.
  std::vector<uint16_t> rep(n);
  std::iota(rep.begin(), rep.end(), uint16_t{0});
  for (size_t k = 0; k < applied; ++k) rep[all[k].vertex] = all[k].target;
  for (const auto& tri : order.gridTriangles) {
    const uint16_t a = find(rep, tri[0]), b = find(rep, tri[1]), c = find(rep, tri[2]);
    if (a == b || b == c || a == c) continue;
    mesh.triangles.push_back({index[a], index[b], index[c]});
  }

  // Order them by removal, last removed first (stable: grid order within a collapse).
  std::vector<uint32_t> removal(mesh.triangles.size(), mesh.collapseCount());
  [[maybe_unused]] const Status replayed = replayCollapses(
      mesh, [](uint32_t, uint32_t) {}, [&](uint32_t j, uint32_t t) { removal[t] = j; },
      TriangleOrder::kAny);
  assert(replayed.ok());  // the collapser's own order is consistent
  std::vector<uint32_t> perm(mesh.triangles.size());
  std::iota(perm.begin(), perm.end(), 0u);
  std::stable_sort(perm.begin(), perm.end(),
                   [&](uint32_t a, uint32_t b) { return removal[a] > removal[b]; });
  std::vector<std::array<uint16_t, 3>> sorted;
  sorted.reserve(perm.size());
  for (uint32_t t : perm) sorted.push_back(mesh.triangles[t]);
  mesh.triangles = std::move(sorted);
  return mesh;
}

Result<std::vector<uint32_t>> triangleRemovals(const ProgressiveMesh& mesh) {
  std::vector<uint32_t> removal(mesh.triangles.size(), mesh.collapseCount());
  const Status s = replayCollapses(
      mesh, [](uint32_t, uint32_t) {}, [&](uint32_t j, uint32_t t) { removal[t] = j; });
  if (!s) return s.error();
  return removal;
}

}  // namespace terralod
