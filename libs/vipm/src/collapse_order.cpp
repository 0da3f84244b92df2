#include "terralod/vipm/collapse_order.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <queue>

#include "patch_mesh.h"

namespace terralod {

std::vector<std::array<uint16_t, 3>> gridTriangulation(int32_t width, int32_t height) {
  std::vector<std::array<uint16_t, 3>> tris;
  tris.reserve(size_t(width - 1) * size_t(height - 1) * 2);
  for (int32_t y = 0; y + 1 < height; ++y) {
    for (int32_t x = 0; x + 1 < width; ++x) {
      const auto v00 = uint16_t(y * width + x), v10 = uint16_t(v00 + 1);
      const auto v01 = uint16_t(v00 + width), v11 = uint16_t(v01 + 1);
      if ((x + y) % 2 == 0) {
        tris.push_back({v00, v10, v11});
        tris.push_back({v00, v11, v01});
      } else {
        tris.push_back({v00, v10, v01});
        tris.push_back({v10, v11, v01});
      }
    }
  }
  return tris;
}

namespace {

// The smallest float not below v, so recorded errors never understate measured ones.
float roundUp(double v) {
  const float f = static_cast<float>(v);
  return double(f) >= v ? f : std::nextafter(f, std::numeric_limits<float>::infinity());
}

struct Candidate {
  double error = std::numeric_limits<double>::infinity();
  uint16_t target = 0;
};

struct Entry {
  double error;
  uint16_t vertex;
  uint32_t stamp;
  // std::priority_queue is a max-heap: "less" means "comes out later".
  bool operator<(const Entry& o) const {
    if (error != o.error) return error > o.error;
    return vertex > o.vertex;
  }
};

// The best collapse of v; its error at least `floor` (the geomorph spacing's hold on v).
Candidate bestCollapse(const PatchMesh& mesh, uint16_t v, double floor,
                       std::vector<uint16_t>& scratch) {
  Candidate best;
  scratch.clear();
  mesh.neighbours(v, scratch);
  std::sort(scratch.begin(), scratch.end());  // deterministic tie-breaks
  for (uint16_t u : scratch) {
    const double e = mesh.collapseError(v, u, best.error);
    if (e < best.error) {
      best = {e, u};
      if (e == 0.0) break;  // nothing beats it
    }
  }
  best.error = std::max(best.error, floor);
  return best;
}

}  // namespace

CollapseOrder buildCollapseOrder(const GridPatch& patch, MaterialRules rules,
                                 const CollapseStart& start) {
  CollapseOrder order;
  order.gridTriangles =
      start.triangles.empty() ? gridTriangulation(patch.width, patch.height) : start.triangles;
  PatchMesh mesh(patch, rules, order.gridTriangles, start.seamX, start.seamY);
  const uint32_t n = patch.pointCount();
  std::vector<Candidate> best(n);
  std::vector<uint32_t> stamp(n, 0);
  // Lazy updates (as in Garland and Heckbert's simplifier): a collapse marks the vertices
  // around it stale instead of re-evaluating them; a stale vertex is re-evaluated when it
  // comes out of the queue and goes back in with its new error. A vertex with no allowed
  // collapse is not queued, so it is re-evaluated at once.
  std::vector<uint8_t> stale(n, 0), queued(n, 0);
  // Per vertex, the error its collapse may not come below (the geomorph spacing). A floor is
  // spread over [floor, kMorphSpan floor) by vertex (Fibonacci hashing), so that a root's
  // first collapses do not all start sliding at the same allowed error.
  std::vector<double> held(n, 0.0);
  for (uint32_t v = 0; v < n; ++v) {
    const double spread = double(uint32_t(v * 2654435769u)) / 4294967296.0;
    held[v] = double(start.errorFloor) * std::pow(kMorphSpan, spread);
  }
  std::priority_queue<Entry> heap;
  std::vector<uint16_t> scratch, ring;
  auto evaluate = [&](uint16_t v) {
    best[v] = bestCollapse(mesh, v, held[v], scratch);
    ++stamp[v];
    stale[v] = 0;
    queued[v] = std::isfinite(best[v].error);
    if (queued[v]) heap.push({best[v].error, v, stamp[v]});
  };
  for (uint32_t v = 0; v < n; ++v) evaluate(uint16_t(v));
  // The full grid's own error: its vertices may sit off the samples (quantised heights).
  double running = 0.0;
  for (uint32_t v = 0; v < n; ++v)
    running = std::max(running, std::abs(double(patch.heights[v]) - patch.vertexHeight(v)));
  // A given start is coarser than the grid: its own error is where the order starts.
  if (!start.triangles.empty()) {
    for (const auto& t : start.triangles)
      running = std::max(running, triangleError(patch, t[0], t[1], t[2]));
    order.startError = roundUp(running);
  }
  while (!heap.empty()) {
    const Entry e = heap.top();
    heap.pop();
    if (e.stamp != stamp[e.vertex] || !mesh.alive(e.vertex)) continue;
    if (stale[e.vertex]) {
      evaluate(e.vertex);
      continue;
    }
    const uint16_t v = e.vertex, u = best[v].target;
    running = std::max(running, e.error);
    const float recorded = roundUp(running);
    if (recorded > start.lastError) break;  // every later one is at least as large
    if (start.spacing == GeomorphSpacing::kOn && recorded > start.bakedError) {
      // v's fan (u included) waits until this collapse has finished sliding.
      ring.clear();
      mesh.neighbours(v, ring);
      const double until = double(roundUp(kMorphSpan * double(recorded)));
      for (uint16_t w : ring) held[w] = std::max(held[w], until);
    }
    mesh.collapse(v, u);
    ++stamp[v];
    queued[v] = 0;
    order.collapses.push_back({v, u, recorded});
    ring.clear();
    mesh.neighbours(u, ring);
    ring.push_back(u);
    for (uint16_t w : ring) {
      if (queued[w]) {
        stale[w] = 1;
      } else {
        evaluate(w);
      }
    }
  }
  return order;
}

}  // namespace terralod
