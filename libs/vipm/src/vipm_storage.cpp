#include "terralod/vipm/vipm_storage.h"

#include <algorithm>
#include <cassert>
#include <cmath>

namespace terralod {

HeightQuantisation chooseQuantisation(const GridPatch& patch, double maxError) {
  const auto [lo, hi] = std::minmax_element(patch.heights.begin(), patch.heights.end());
  double step = std::exp2(std::floor(std::log2(std::max(maxError, 1e-6) / 8.0)));
  while ((double(*hi) - double(*lo)) / step > 65000.0) step *= 2.0;
  return {std::floor(double(*lo) / step) * step, step};
}

void quantiseVertexHeights(GridPatch& patch, const HeightQuantisation& q) {
  patch.vertexHeights.resize(patch.heights.size());
  for (size_t i = 0; i < patch.heights.size(); ++i) {
    const double level = std::round((double(patch.heights[i]) - q.zBase) / q.zStep);
    patch.vertexHeights[i] = float(q.zBase + std::clamp(level, 0.0, 65535.0) * q.zStep);
  }
}

VipmChunkData packChunk(const GridPatch& patch, const ProgressiveMesh& mesh,
                        const HeightQuantisation& q) {
  VipmChunkData c;
  assert(mesh.patchIds.size() == mesh.points.size());
  c.width = uint16_t(mesh.width);
  c.height = uint16_t(mesh.height);
  c.zBase = q.zBase;
  c.zStep = q.zStep;
  c.finestError = mesh.finestError;
  c.points = mesh.points;
  for (uint16_t p : mesh.patchIds) {
    const double level = std::round((double(patch.vertexHeight(p)) - q.zBase) / q.zStep);
    c.heights.push_back(uint16_t(std::clamp(level, 0.0, 65535.0)));
    c.materials.push_back(patch.materials[p]);
  }
  c.targets = mesh.targets;
  const float largest = mesh.errors.empty() ? 0.0f : mesh.errors.back();
  c.errorStep = largest > 0 ? std::nextafter(largest / 65535.0f, 1e30f) : 1.0f;
  for (float e : mesh.errors) {
    double level = std::ceil(double(e) / double(c.errorStep));
    while (level * double(c.errorStep) < double(e)) level += 1;
    c.errors.push_back(uint16_t(std::min(level, 65535.0)));
  }
  for (const auto& t : mesh.triangles) c.indices.insert(c.indices.end(), t.begin(), t.end());
  return c;
}

UnpackedChunk unpackChunk(const VipmChunkData& c) {
  UnpackedChunk u;
  ProgressiveMesh& m = u.mesh;
  m.width = c.width;
  m.height = c.height;
  m.points = c.points;
  m.targets = c.targets;
  m.finestError = c.finestError;
  for (uint16_t e : c.errors) {
    const double exact = double(e) * double(c.errorStep);
    const float f = float(exact);  // rounded up: a stored error never understates
    m.errors.push_back(double(f) >= exact ? f : std::nextafter(f, 1e30f));
  }
  for (size_t i = 0; i + 2 < c.indices.size(); i += 3)
    m.triangles.push_back({c.indices[i], c.indices[i + 1], c.indices[i + 2]});
  for (uint32_t v = 0; v < c.vertexCount(); ++v) {
    const uint32_t p = c.points[v];
    u.positions.push_back(
        {float(p % c.width), float(p / c.width), float(c.zBase + double(c.heights[v]) * c.zStep)});
  }
  u.materials = c.materials;
  return u;
}

}  // namespace terralod
