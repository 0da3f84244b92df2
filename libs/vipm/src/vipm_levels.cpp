#include "terralod/vipm/vipm_levels.h"

#include <algorithm>
#include <bit>

#include "collapse_replay.h"

namespace terralod {

Result<VipmLevels> VipmLevels::reconstruct(const ProgressiveMesh& mesh,
                                           std::span<const uint8_t> vertexMaterials,
                                           MaterialFade fade) {
  const uint32_t n = mesh.vertexCount(), r = mesh.collapseCount();
  const uint32_t triangleCount = uint32_t(mesh.triangles.size());
  if (vertexMaterials.size() != n) return Error{"material count differs from vertex count"};
  for (uint8_t m : vertexMaterials)
    if (m >= 8) return Error{"material index out of range"};

  // First replay: which materials each triangle's corners ever have, and the moves.
  std::vector<uint8_t> mask(triangleCount, 0);
  for (uint32_t t = 0; t < triangleCount; ++t)
    for (uint16_t v : mesh.triangles[t])
      if (v < n) mask[t] |= uint8_t(1u << vertexMaterials[v]);
  std::vector<uint32_t> wholeMoveStart(r + 1, 0);
  std::vector<uint32_t> wholeMoves;
  std::vector<uint32_t> deaths(r, 0);
  uint32_t current = 0;
  const Status s = replayCollapses(
      mesh,
      [&](uint32_t j, uint32_t corner) {
        while (current < j) wholeMoveStart[++current] = uint32_t(wholeMoves.size());
        wholeMoves.push_back(corner);
        mask[corner / 3] |= uint8_t(1u << vertexMaterials[mesh.targets[j]]);
      },
      [&](uint32_t j, uint32_t) { ++deaths[j]; });
  if (!s) return s.error();
  while (current < r) wholeMoveStart[++current] = uint32_t(wholeMoves.size());
  if (fade == MaterialFade::kToTarget) {
    // A vertex can show any material along its chain of targets (vertex n - 1 - j collapses
    // onto targets[j], an earlier vertex, which the replay checked).
    std::vector<uint8_t> chain(n);
    for (uint32_t v = 0; v < n; ++v) {
      chain[v] = uint8_t(1u << vertexMaterials[v]);
      if (v >= n - r) chain[v] |= chain[mesh.targets[n - 1 - v]];
    }
    for (uint32_t t = 0; t < triangleCount; ++t)
      for (uint16_t v : mesh.triangles[t])
        if (v < n) mask[t] |= chain[v];
  }

  VipmLevels levels;
  levels.mVertexCount = n;
  levels.mTargets = mesh.targets;
  levels.mRemoved.resize(r);
  for (uint32_t j = 0; j < r; ++j) levels.mRemoved[j] = uint16_t(n - 1 - j);

  // The whole chunk's part.
  VipmPart whole;
  whole.indices.reserve(size_t(triangleCount) * 3);
  for (const auto& tri : mesh.triangles)
    whole.indices.insert(whole.indices.end(), tri.begin(), tri.end());
  whole.triangles.resize(r + 1);
  whole.triangles[0] = triangleCount;
  for (uint32_t j = 0; j < r; ++j) whole.triangles[j + 1] = whole.triangles[j] - deaths[j];
  whole.moveStart = wholeMoveStart;
  whole.moves = wholeMoves;

  // One part per material present: its triangles in the same order, moves mapped.
  uint8_t present = 0;
  for (uint8_t m : mask) present |= m;
  std::vector<uint32_t> local(triangleCount);
  levels.mParts.push_back(std::move(whole));
  for (int m = 0; m < 8; ++m) {
    if (!(present & (1u << m))) continue;
    const VipmPart& w = levels.mParts.front();
    VipmPart part;
    part.material = m;
    uint32_t count = 0;
    std::vector<uint32_t> prefixIn(triangleCount + 1, 0);  // part triangles among the first t
    for (uint32_t t = 0; t < triangleCount; ++t) {
      prefixIn[t] = count;
      if (mask[t] & (1u << m)) {
        local[t] = count++;
        part.wholeTriangles.push_back(t);
        part.indices.insert(part.indices.end(), w.indices.begin() + 3 * t,
                            w.indices.begin() + 3 * t + 3);
      } else {
        local[t] = UINT32_MAX;
      }
    }
    prefixIn[triangleCount] = count;
    part.triangles.resize(r + 1);
    for (uint32_t j = 0; j <= r; ++j) part.triangles[j] = prefixIn[w.triangles[j]];
    part.moveStart.resize(r + 1, 0);
    for (uint32_t j = 0; j < r; ++j) {
      part.moveStart[j] = uint32_t(part.moves.size());
      for (uint32_t i = w.moveStart[j]; i < w.moveStart[j + 1]; ++i) {
        const uint32_t t = w.moves[i] / 3;
        if (local[t] != UINT32_MAX) part.moves.push_back(3 * local[t] + w.moves[i] % 3);
      }
    }
    part.moveStart[r] = uint32_t(part.moves.size());
    levels.mParts.push_back(std::move(part));
  }
  return levels;
}

void VipmLevels::setApplied(uint32_t count) {
  count = std::min(count, collapseCount());
  while (mApplied < count) {
    const uint32_t j = mApplied++;
    for (VipmPart& p : mParts) {
      for (uint32_t i = p.moveStart[j]; i < p.moveStart[j + 1]; ++i)
        p.indices[p.moves[i]] = mTargets[j];
      p.dirty = true;
    }
  }
  while (mApplied > count) {
    const uint32_t j = --mApplied;
    for (VipmPart& p : mParts) {
      for (uint32_t i = p.moveStart[j]; i < p.moveStart[j + 1]; ++i)
        p.indices[p.moves[i]] = mRemoved[j];
      p.dirty = true;
    }
  }
}

uint32_t collapsesWithin(std::span<const float> errors, double e) {
  return uint32_t(std::upper_bound(errors.begin(), errors.end(), e,
                                   [](double x, float y) { return x < double(y); }) -
                  errors.begin());
}

MorphWindow morphWindow(std::span<const float> errors, double theta, Geomorph geomorph) {
  if (geomorph == Geomorph::kOff) {
    const uint32_t n = collapsesWithin(errors, theta);
    return {n, n};
  }
  return {collapsesWithin(errors, theta / kMorphSpan), collapsesWithin(errors, theta)};
}

MorphWindow morphWindow(std::span<const float> errors, double theta, double morphTheta,
                        Geomorph geomorph) {
  if (geomorph == Geomorph::kOff) return morphWindow(errors, theta, geomorph);
  return {collapsesWithin(errors, std::min(theta, morphTheta) / kMorphSpan),
          collapsesWithin(errors, std::max(theta, morphTheta))};
}

void morphPositions(const ProgressiveMesh& mesh, const MorphWindow& window, double theta,
                    std::span<const std::array<float, 3>> own,
                    std::span<std::array<float, 3>> drawn) {
  const uint32_t n = mesh.vertexCount();
  for (uint32_t j = window.morphing; j-- > window.applied;) {
    const uint32_t v = n - 1 - j, u = mesh.targets[j];
    const uint32_t uCollapse = n - 1 - u;  // the collapse that removes u, if any
    const bool uMorphs = uCollapse >= window.applied && uCollapse < window.morphing;
    const std::array<float, 3>& to = uMorphs ? drawn[u] : own[u];
    const float t = morphProgress(theta, double(mesh.errors[j]));
    for (int k = 0; k < 3; ++k) drawn[v][k] = own[v][k] + t * (to[k] - own[v][k]);
  }
}

void morphMaterialWeights(const ProgressiveMesh& mesh, const MorphWindow& window, double theta,
                          std::span<const uint8_t> materials, std::span<MaterialWeights> weights) {
  const uint32_t n = mesh.vertexCount();
  for (uint32_t j = window.morphing; j-- > window.applied;) {
    const uint32_t v = n - 1 - j;
    const MaterialWeights& to = weights[mesh.targets[j]];  // its own, or drawn: set already
    const float t = morphProgress(theta, double(mesh.errors[j]));
    MaterialWeights& w = weights[v];
    for (int m = 0; m < kMaxMaterials; ++m)
      w[size_t(m)] = (1.0f - t) * (materials[v] == m ? 1.0f : 0.0f) + t * to[size_t(m)];
  }
}

}  // namespace terralod
