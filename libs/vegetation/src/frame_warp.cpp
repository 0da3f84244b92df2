#include "terralod/vegetation/frame_warp.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>

#include <glm/gtc/matrix_transform.hpp>

#include "terralod/core/parallel.h"

namespace terralod::veg {
namespace {

constexpr double kNear = 0.05;  // metres, as the terrain's projection

double msSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
      .count();
}

// Cuts `work` (per tile, in order) into `parts` runs of about equal sums; returns the first
// index of each run and the end.
std::vector<size_t> balancedRuns(const std::vector<uint64_t>& work, unsigned parts) {
  uint64_t total = 0;
  for (uint64_t w : work) total += w;
  std::vector<size_t> bounds{0};
  uint64_t sum = 0;
  for (size_t i = 0; i < work.size() && bounds.size() < parts; ++i) {
    sum += work[i];
    if (sum * parts >= total * bounds.size()) bounds.push_back(i + 1);
  }
  while (bounds.size() <= parts) bounds.push_back(work.size());
  return bounds;
}

void clearTarget(WarpTarget& t, int width, int height) {
  if (t.width != width || t.height != height)
    t = WarpTarget(width, height);
  else
    t.clear();
}

}  // namespace

HalfTransform halfTransform(const View& view, const TileOnTerrain& tile, TileHalf half,
                            double farPlane) {
  const glm::dmat4 rotation = glm::lookAt(glm::dvec3(0.0), view.forward, view.up);
  glm::dmat4 projection(0.0);
  projection[0][0] = 1.0 / view.tanHalfWidth;
  projection[1][1] = 1.0 / view.tanHalfHeight;
  projection[2][2] = -(farPlane + kNear) / (farPlane - kNear);
  projection[2][3] = -1.0;
  projection[3][2] = -2.0 * farPlane * kNear / (farPlane - kNear);
  const glm::dmat4 shear(halfShear(tile, half));
  // The eye-relative translation in double: tiles lie kilometres from the origin.
  const glm::dmat4 toEye = glm::translate(glm::dmat4(1.0), -view.camera.eye);
  const glm::dmat4 tileToClip = projection * rotation * toEye * shear;
  const glm::dvec4 eye = glm::inverse(shear) * glm::dvec4(view.camera.eye, 1.0);
  return {glm::mat4(tileToClip), glm::vec3(eye)};
}

float frameDepthToDistance(float windowDepth, double farPlane) {
  const double z = 2.0 * double(windowDepth) - 1.0;
  return float(2.0 * farPlane * kNear / ((farPlane + kNear) - z * (farPlane - kNear)));
}

FrameWarpStats FrameWarper::warp(std::span<const TileDraw> tiles, LdiSource& ldis, const View& view,
                                 const FrameWarpOptions& options, const PictureSpans& out) {
  FrameWarpStats stats;
  const auto start = std::chrono::steady_clock::now();
  // The LDIs first, on this thread (the source need not be thread-safe): one job per LDI a
  // tile draws, in the tiles' order.
  ldis.beginFrame();
  struct Job {
    size_t tile;
    const WarpLdi* ldi;
    float opacity;
  };
  std::vector<Job> jobs;
  std::vector<uint64_t> work;
  std::vector<bool> missing(tiles.size(), false);
  double farthest = 1.0;
  for (size_t i = 0; i < tiles.size(); ++i) {
    const TileDraw& t = tiles[i];
    for (int k = 0; k < t.ldiCount; ++k) {
      const TileLdi& l = t.ldis[size_t(k)];
      const WarpLdi* ldi = ldis.ldi(t.prototile, l.resolution, l.direction);
      if (!ldi) {
        missing[i] = true;
        continue;
      }
      jobs.push_back({i, ldi, l.opacity});
      work.push_back(ldis.depthPixels(t.prototile, l.resolution, l.direction));
    }
    farthest = std::max(farthest, t.distance + 2.0 * double(t.placement.size));
  }
  for (bool m : missing) stats.missingLdis += m;
  const double farPlane = 2.0 * farthest;
  const unsigned parts = std::max(1u, std::min<unsigned>(options.threads, unsigned(jobs.size())));
  const std::vector<size_t> runs = balancedRuns(work, parts);
  if (mTargets.size() < parts) mTargets.resize(parts, WarpTarget(0, 0));
  std::vector<FrameWarpStats> partStats(parts);
  parallelFor(parts, parts, [&](size_t part, unsigned) {
    WarpTarget& target = mTargets[part];
    clearTarget(target, out.width, out.height);
    FrameWarpStats& ps = partStats[part];
    for (size_t j = runs[part]; j < runs[part + 1]; ++j) {
      const Job& job = jobs[j];
      const TileDraw& t = tiles[job.tile];
      WarpOptions o = options.warp;
      o.opacity = job.opacity;
      const auto& c = t.placement.heights;  // SW, SE, NE, NW
      const double twist = std::abs(double(c[1]) + c[3] - c[0] - c[2]);
      if (twist * t.screenPixels / t.placement.size < options.onePassTwistPixels) {
        const HalfTransform se = halfTransform(view, t.placement, TileHalf::kSouthEast, farPlane);
        o.onlyHalf.reset();
        o.northWestToClip =
            halfTransform(view, t.placement, TileHalf::kNorthWest, farPlane).tileToClip;
        ps.splats += warpLdi(*job.ldi, se.tileToClip, se.eyeInTile, target, o).splats;
        ++ps.onePassTiles;
      } else {
        const TileHalf far = farHalf(t.placement, glm::vec3(view.camera.eye));
        for (TileHalf half :
             {far, far == TileHalf::kSouthEast ? TileHalf::kNorthWest : TileHalf::kSouthEast}) {
          const HalfTransform h = halfTransform(view, t.placement, half, farPlane);
          o.onlyHalf = half;
          o.northWestToClip.reset();
          ps.splats += warpLdi(*job.ldi, h.tileToClip, h.eyeInTile, target, o).splats;
        }
      }
      ps.depthPixels += work[j];
      ++ps.ldis;
      // A tile counts once: in the part that draws its first LDI.
      if (j == 0 || jobs[j - 1].tile != job.tile) ++ps.tiles;
    }
  });
  for (const FrameWarpStats& ps : partStats) {
    stats.tiles += ps.tiles;
    stats.ldis += ps.ldis;
    stats.onePassTiles += ps.onePassTiles;
    stats.splats += ps.splats;
    stats.depthPixels += ps.depthPixels;
  }
  stats.warpMs = msSince(start);

  const auto mergeStart = std::chrono::steady_clock::now();
  // Only the rows some target drew in; the picture holds nothing outside them.
  stats.top = out.height;
  stats.bottom = 0;
  for (unsigned p = 0; p < parts; ++p) {
    stats.top = std::min(stats.top, mTargets[p].dirtyTop);
    stats.bottom = std::max(stats.bottom, mTargets[p].dirtyBottom);
  }
  const int width = out.width;
  const int top = stats.top, rows = std::max(0, stats.bottom - stats.top);
  const unsigned bands = std::max(1u, std::min<unsigned>(options.threads, unsigned(rows)));
  parallelFor(rows > 0 ? bands : 0, bands, [&](size_t band, unsigned) {
    const int rowBegin = top + int(size_t(rows) * band / bands);
    const int rowEnd = top + int(size_t(rows) * (band + 1) / bands);
    struct Layer {
      float depth;
      const float* rgba;
    };
    std::array<Layer, 64> layers;
    const unsigned used = std::min<unsigned>(parts, unsigned(layers.size()));
    for (size_t i = size_t(rowBegin) * width; i < size_t(rowEnd) * width; ++i) {
      size_t n = 0;
      for (unsigned p = 0; p < used; ++p)
        if (mTargets[p].rgba[4 * i + 3] > 0.0f)
          layers[n++] = {mTargets[p].depth[i], &mTargets[p].rgba[4 * i]};
      if (n == 0) {
        out.rgba[i] = 0;
        out.viewDepth[i] = std::numeric_limits<float>::infinity();
        continue;
      }
      if (n == 1) {
        out.rgba[i] = packRgba8(layers[0].rgba);
        out.viewDepth[i] = frameDepthToDistance(layers[0].depth, farPlane);
        continue;
      }
      // Farther first, each nearer one over what is under it.
      std::sort(layers.begin(), layers.begin() + ptrdiff_t(n),
                [](const Layer& a, const Layer& b) { return a.depth > b.depth; });
      float c[4] = {0, 0, 0, 0};
      for (size_t k = 0; k < n; ++k) {
        const float* src = layers[k].rgba;
        for (int j = 0; j < 4; ++j) c[j] = src[j] + c[j] * (1.0f - src[3]);
      }
      out.rgba[i] = packRgba8(c);
      out.viewDepth[i] = frameDepthToDistance(layers[n - 1].depth, farPlane);
    }
  });
  stats.mergeMs = msSince(mergeStart);
  return stats;
}

}  // namespace terralod::veg
