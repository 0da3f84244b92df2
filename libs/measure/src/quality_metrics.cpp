#include "terralod/measure/quality_metrics.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <mutex>

#include "sample_key.h"
#include "terralod/core/parallel.h"
#include "terralod/core/sample_raster.h"
#include "terralod/format/chunk_position.h"

namespace terralod {

QualityMetrics::QualityMetrics(const TilesetReader& tileset, const ChunkTree& tree,
                               const Heightfield& source, int stride, unsigned threads)
    : mTileset(tileset),
      mTree(tree),
      mSource(source),
      mStride(std::max(stride, 1)),
      mThreads(std::max(threads, 1u)),
      mMark(tree.nodes().size(), 0) {}

Result<const QualityMetrics::CachedChunk*> QualityMetrics::chunk(uint32_t node) {
  auto it = mChunks.find(node);
  if (it != mChunks.end()) return &it->second;
  auto decoded = mTileset.readChunk(node);
  if (!decoded) return decoded.error();
  CachedChunk c;
  c.geometry = std::move(decoded).value();
  c.truthMin = 1e300;
  c.truthMax = -1e300;
  const TilesetHeader& h = mTileset.header();
  const auto [x0, y0] = chunkCellOrigin(h, mTileset.nodes()[node]);
  const int64_t side = h.chunkCells(mTileset.nodes()[node].level);
  for (int64_t y = y0; y <= std::min<int64_t>(y0 + side, mSource.rows() - 1); ++y)
    for (int64_t x = x0; x <= std::min<int64_t>(x0 + side, mSource.columns() - 1); ++x) {
      const double z = mSource(int32_t(x), int32_t(y));
      c.truthMin = std::min(c.truthMin, z);
      c.truthMax = std::max(c.truthMax, z);
    }
  c.truthBox.min = {double(x0) * mTree.spacing()[0], double(y0) * mTree.spacing()[1], c.truthMin};
  c.truthBox.max = {
      double(std::min<int64_t>(x0 + side, mSource.columns() - 1)) * mTree.spacing()[0],
      double(std::min<int64_t>(y0 + side, mSource.rows() - 1)) * mTree.spacing()[1], c.truthMax};
  measureChunkError(node, c);
  return &mChunks.emplace(node, std::move(c)).first->second;
}

void QualityMetrics::measureChunkError(uint32_t node, CachedChunk& c) const {
  size_t triangles = 0;
  for (const ChunkPart& part : c.geometry.parts) triangles += part.surfaceIndexCount / 3;
  c.triangleError.assign(triangles, 0.0f);
  size_t triangle = 0;
  auto measure = [&](int64_t x, int64_t y, double z) {
    const double e = std::fabs(z - mSource(int32_t(x), int32_t(y)));
    float& slot = c.triangleError[triangle];
    // Rounded up to the next float, so that the bound never falls below the double it bounds.
    if (e > slot) slot = std::nextafter(float(e), std::numeric_limits<float>::infinity());
  };
  for (double t : {0.0, 1.0})
    rasterizeChunk(node, c, t, nullptr, measure, [&](size_t index, const Box&) {
      triangle = index;
      return true;
    });
  c.error = triangles ? *std::max_element(c.triangleError.begin(), c.triangleError.end()) : 0.0;
}

bool QualityMetrics::inView(const View& view, int64_t x, int64_t y, double z) const {
  const glm::dvec3 p{double(x) * mTree.spacing()[0], double(y) * mTree.spacing()[1], z};
  for (const glm::dvec4& plane : view.planes)
    if (glm::dot(glm::dvec3(plane), p) + plane.w < 0.0) return false;
  return true;
}

template <typename Visit, typename Keep>
void QualityMetrics::rasterizeChunk(uint32_t node, const CachedChunk& cached, double morph,
                                    const View* view, Visit&& visit, Keep&& keep) const {
  const ChunkGeometry& geometry = cached.geometry;
  const TilesetHeader& h = mTileset.header();
  const auto [x0, y0] = chunkCellOrigin(h, mTileset.nodes()[node]);
  const int64_t side = h.chunkCells(mTileset.nodes()[node].level);
  const int64_t maxX = std::min<int64_t>(x0 + side, mSource.columns() - 1);
  const int64_t maxY = std::min<int64_t>(y0 + side, mSource.rows() - 1);
  const int64_t s = mStride;
  size_t triangle = 0;
  for (const ChunkPart& part : geometry.parts)
    for (uint32_t k = 0; k + 2 < part.surfaceIndexCount; k += 3, ++triangle) {
      SampleVertex v[3];
      for (int j = 0; j < 3; ++j) {
        const ChunkVertex& cv = part.vertices[part.indices[k + j]];
        v[j] = {x0 + cv.x, y0 + cv.y, chunkVertexHeight(geometry, cv, morph)};
      }
      // Samples are tested in view at their true height; the drawn surface may lie anywhere
      // between, so the triangle's box spans both.
      Box box;
      box.min = {double(std::min({v[0].x, v[1].x, v[2].x})) * mTree.spacing()[0],
                 double(std::min({v[0].y, v[1].y, v[2].y})) * mTree.spacing()[1],
                 std::min({v[0].z, v[1].z, v[2].z, cached.truthMin})};
      box.max = {double(std::max({v[0].x, v[1].x, v[2].x})) * mTree.spacing()[0],
                 double(std::max({v[0].y, v[1].y, v[2].y})) * mTree.spacing()[1],
                 std::max({v[0].z, v[1].z, v[2].z, cached.truthMax})};
      if (!keep(triangle, box)) continue;
      if (view && !boxInFrustum(*view, box)) continue;
      if (s == 1) {
        rasterizeTriangle(v[0], v[1], v[2], x0, maxX, y0, maxY, visit);
      } else {
        rasterizeTriangle(v[0], v[1], v[2], x0, maxX, y0, maxY,
                          [&](int64_t x, int64_t y, double z) {
                            if (x % s == 0 && y % s == 0) visit(x, y, z);
                          });
      }
    }
}

Result<double> QualityMetrics::maxErrorPixels(const View& view,
                                              std::span<const SelectedChunk> selection) {
  // Decode on this thread (the cache is not thread-safe), then measure in parallel.
  struct Candidate {
    const SelectedChunk* chunk;
    const CachedChunk* cached;
    double bound;  // no sample of the chunk can show a larger error, pixels
  };
  std::vector<Candidate> candidates;
  candidates.reserve(selection.size());
  const glm::dvec2 spacing{mTree.spacing()[0], mTree.spacing()[1]};
  for (const SelectedChunk& c : selection) {
    auto cached = chunk(c.node);
    if (!cached) return cached.error();
    candidates.push_back({&c, *cached,
                          screenSpaceError(view, (*cached)->error,
                                           distanceToBox(view.camera.eye, (*cached)->truthBox))});
  }
  // The worst error can only be where the bounds allow it: measure the chunks and triangles
  // with the largest bounds first and skip those whose bound cannot beat the worst found so
  // far. The result is the same as measuring every sample, much faster.
  std::sort(candidates.begin(), candidates.end(),
            [](const Candidate& a, const Candidate& b) { return a.bound > b.bound; });
  std::atomic<double> found{0.0};
  parallelFor(candidates.size(), mThreads, [&](size_t i, unsigned) {
    const Candidate& c = candidates[i];
    double worst = found.load(std::memory_order_relaxed);
    if (c.bound <= worst) return;
    // Samples are in view at their true heights: none where the box of those lies outside a
    // plane, every one where it lies inside all (then not tested one by one).
    if (!boxInFrustum(view, c.cached->truthBox)) return;
    const bool allInView = boxWithinFrustum(view, c.cached->truthBox);
    rasterizeChunk(
        c.chunk->node, *c.cached, c.chunk->morph, &view,
        [&](int64_t x, int64_t y, double z) {
          const double truth = mSource(int32_t(x), int32_t(y));
          if (!allInView && !inView(view, x, y, truth)) return;
          const glm::dvec3 p{double(x) * spacing.x, double(y) * spacing.y, truth};
          const double distance = glm::length(p - view.camera.eye);
          worst = std::max(worst, screenSpaceError(view, std::fabs(z - truth), distance));
        },
        [&](size_t triangle, const Box& box) {
          return screenSpaceError(view, c.cached->triangleError[triangle],
                                  distanceToBox(view.camera.eye, box)) > worst;
        });
    double seen = found.load(std::memory_order_relaxed);
    while (worst > seen && !found.compare_exchange_weak(seen, worst)) {
    }
  });
  return found.load();
}

Result<double> QualityMetrics::maxPopPixels(const View& view, const SelectionOptions& options,
                                            std::span<const SelectedChunk> previous,
                                            std::span<const SelectedChunk> current) {
  // Only where the two selections differ can the surfaces differ: chunks in both are drawn
  // with the same morph parameter (frame i's) in both.
  for (const SelectedChunk& c : previous) mMark[c.node] |= 1;
  for (const SelectedChunk& c : current) mMark[c.node] |= 2;
  std::vector<uint32_t> gone, added;
  for (const SelectedChunk& c : previous)
    if (mMark[c.node] == 1) gone.push_back(c.node);
  for (const SelectedChunk& c : current)
    if (mMark[c.node] == 2) added.push_back(c.node);
  for (const SelectedChunk& c : previous) mMark[c.node] = 0;
  for (const SelectedChunk& c : current) mMark[c.node] = 0;
  if (gone.empty() || added.empty()) return 0.0;

  for (const std::vector<uint32_t>* nodes : {&gone, &added})
    for (uint32_t node : *nodes)
      if (auto cached = chunk(node); !cached) return cached.error();
  // A sample on a border between chunks of different levels has one height in each (the
  // T-junction gap the skirts cover); it pops only if no height after meets a height before,
  // so each side keeps the range of its chunks' heights there. Inside a chunk the range is one
  // height. (Keeping the last chunk's height instead measured a 1.2 px pop where a coarser
  // neighbour's height, never drawn over that sample's pixel, met the new chunk's.)
  struct Range {
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    glm::dvec3 at;  // a point of the sample at its height after, for the distance
    void add(double z) { lo = std::min(lo, z), hi = std::max(hi, z); }
  };
  std::unordered_map<uint64_t, Range> before, after;
  for (uint32_t node : gone)
    rasterizeChunk(node, morphParameter(mTree, view, options, node), view,
                   [&](int64_t x, int64_t y, double z) { before[sampleKey(x, y)].add(z); });
  for (uint32_t node : added)
    rasterizeChunk(node, morphParameter(mTree, view, options, node), view,
                   [&](int64_t x, int64_t y, double z) {
                     if (!before.count(sampleKey(x, y))) return;
                     const double truth = mSource(int32_t(x), int32_t(y));
                     if (!inView(view, x, y, truth)) return;
                     Range& r = after[sampleKey(x, y)];
                     r.add(z);
                     r.at = {double(x) * mTree.spacing()[0], double(y) * mTree.spacing()[1], z};
                   });
  double worst = 0.0;
  for (const auto& [key, a] : after) {
    const Range& b = before.at(key);
    const double gap = std::max({0.0, a.lo - b.hi, b.lo - a.hi});
    worst = std::max(worst, screenSpaceError(view, gap, glm::length(a.at - view.camera.eye)));
  }
  return worst;
}

uint64_t QualityMetrics::holes(const Image& image, const View& view,
                               std::array<uint8_t, 3> background) const {
  const Box& e = mTree.extent();
  // A pixel spans at most this angle (radians; off-axis pixels span less), so at most
  // pixelAngle * t metres at distance t along its ray.
  const double pixelAngle = 2.0 * view.tanHalfWidth / image.width;
  auto overData = [&](const glm::dvec3& ray, double z) {
    if (ray.z >= 0.0) return false;  // never comes down to the terrain
    const double t = (z - view.camera.eye.z) / ray.z;
    if (t < -1e-9) return false;
    const glm::dvec3 p = view.camera.eye + ray * t;
    // Inside the data's footprint by more than the rasteriser's rounding of its outer edge
    // (which has no skirt: nothing lies beyond it to cover).
    const double margin = kRasterPrecisionPx * pixelAngle * std::max(t, 0.0);
    return p.x >= e.min[0] + margin && p.x <= e.max[0] - margin && p.y >= e.min[1] + margin &&
           p.y <= e.max[1] - margin;
  };
  // Every level's drawn surface lies within its error of the data, the coarsest error of all.
  const double slack = mTree.levelError(0);
  const double lowest = e.min[2] - slack, highest = e.max[2] + slack;
  uint64_t holes = 0;
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) {
      const auto px = image.pixel(x, y);
      if (px[0] != background[0] || px[1] != background[1] || px[2] != background[2]) continue;
      // The pixel's ray, through its centre (row 0 is the top).
      const double u = (2.0 * (x + 0.5) / image.width - 1.0) * view.tanHalfWidth;
      const double v = (1.0 - 2.0 * (y + 0.5) / image.height) * view.tanHalfHeight;
      const glm::dvec3 ray = glm::normalize(view.forward + view.right * u + view.up * v);
      // Over the data all the way down from the eye (or the drawn surface's highest point, if
      // lower) to the drawn surface's lowest: starting above the surface and ending below it,
      // the ray must have met it.
      const double top = std::min(view.camera.eye.z, highest);
      if (overData(ray, top) && overData(ray, lowest)) ++holes;
    }
  return holes;
}

Camera lookDownCamera(const View& view) {
  Camera c = view.camera;
  glm::dvec2 heading(view.forward.x, view.forward.y);
  if (glm::length(heading) < 1e-9) heading = {view.up.x, view.up.y};
  heading = glm::normalize(heading);
  const double pitch = -60.0 * 3.14159265358979323846 / 180.0;
  c.target = c.eye + glm::dvec3(heading * std::cos(pitch), std::sin(pitch)) * 100.0;
  return c;
}

}  // namespace terralod
