#include "terralod/vegetation/ldi_warp.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

namespace terralod::veg {
namespace {

// Clip coordinates of a depth pixel are affine in (column, row, depth): base + c·col + r·row +
// t·depth, so a pixel costs three multiply-adds (Shade's incremental warp).
struct ClipBasis {
  glm::vec4 base, column, row, depth;
};

ClipBasis basisOf(const LdiCamera& cam, const glm::mat4& m) {
  const glm::vec3 first = cam.origin + 0.5f * cam.pixelSize * (cam.axisU + cam.axisV);
  return {m * glm::vec4(first, 1.0f), m * glm::vec4(cam.pixelSize * cam.axisU, 0.0f),
          m * glm::vec4(cam.pixelSize * cam.axisV, 0.0f), m * glm::vec4(cam.direction, 0.0f)};
}

// Where the clip-space step `d` moves the point at `clip`, in target pixels.
float pixelsMoved(const glm::vec4& clip, const glm::vec4& d, const WarpTarget& t) {
  const float w = clip.w;
  const float x = (d.x * w - clip.x * d.w) / (w * w), y = (d.y * w - clip.y * d.w) / (w * w);
  return std::hypot(x * 0.5f * float(t.width), y * 0.5f * float(t.height));
}

class Splatter {
 public:
  Splatter(const Ldi& ldi, const ClipBasis& basis, const glm::vec3& eye, WarpTarget& target,
           const WarpOptions& options)
      : mLdi(ldi), mBasis(basis), mEye(eye), mTarget(target), mOptions(options) {
    const LdiCamera& c = ldi.camera;
    mDepthStep = (c.depthMax - c.depthMin) / float(kLdiMaxDepth);
    mEyeDepth = glm::dot(eye, c.direction);
    // Where each pixel's layers start.
    mFirst.resize(ldi.layerCounts.size() + 1, 0);
    for (size_t i = 0; i < ldi.layerCounts.size(); ++i)
      mFirst[i + 1] = mFirst[i] + ldi.layerCounts[i];
  }

  // Draws pixel (column, row)'s layers, those farther from the eye along the rays first.
  void pixel(uint32_t column, uint32_t row) {
    const size_t index = size_t(row) * mLdi.camera.width + column;
    size_t lo = mFirst[index], hi = mFirst[index + 1];
    if (lo == hi) return;
    const glm::vec4 at = mBasis.base + float(column) * mBasis.column + float(row) * mBasis.row;
    if (mOptions.order == WarpOrder::kRowMajor) {
      for (size_t k = lo; k < hi; ++k) layer(at, column, row, mLdi.pixels[k]);
      return;
    }
    // Layers are stored front first; take from whichever end lies farther from the eye.
    while (lo < hi) {
      const float front = std::abs(depthOf(mLdi.pixels[lo]) - mEyeDepth);
      const float back = std::abs(depthOf(mLdi.pixels[hi - 1]) - mEyeDepth);
      if (back >= front)
        layer(at, column, row, mLdi.pixels[--hi]);
      else
        layer(at, column, row, mLdi.pixels[lo++]);
    }
  }

  WarpStats stats;

 private:
  float depthOf(const DepthPixel& p) const {
    return mLdi.camera.depthMin + float(p.depth()) * mDepthStep;
  }

  void layer(const glm::vec4& at, uint32_t column, uint32_t row, const DepthPixel& p) {
    ++stats.depthPixels;
    if (mOptions.onlyHalf) {
      const glm::vec3 point = ldiPointOf(column, row, p);
      if (halfOf(point.x, point.y) != *mOptions.onlyHalf) return;
    }
    const glm::vec4 clip = at + depthOf(p) * mBasis.depth;
    if (clip.w <= 1e-6f) return;  // behind the eye
    const float x = clip.x / clip.w, y = clip.y / clip.w, z = clip.z / clip.w;
    if (z < -1 || z > 1) return;
    const float px = (x * 0.5f + 0.5f) * float(mTarget.width);
    const float py = (0.5f - y * 0.5f) * float(mTarget.height);
    int side = 1;
    if (mOptions.sizedSplats) {
      // The LDI pixel's footprint here, grown by how obliquely the LDI saw the surface against
      // how squarely the eye sees it (the splat index is the surface normal).
      float size = std::max(pixelsMoved(clip, mBasis.column, mTarget),
                            pixelsMoved(clip, mBasis.row, mTarget));
      const glm::vec3 n = decodeSplatNormal(p.splat());
      const glm::vec3 point = ldiPointOf(column, row, p);
      const glm::vec3 toEye = glm::normalize(mEye - point);
      const float seenByLdi = std::max(0.3f, std::abs(glm::dot(n, mLdi.camera.direction)));
      size *= std::sqrt(std::clamp(std::abs(glm::dot(n, toEye)) / seenByLdi, 0.5f, 2.0f));
      side = std::clamp(int(std::ceil(size - 0.01f)), 1, mOptions.maxSplat);  // 1.0001 is 1
    }
    const int x0 = int(std::floor(px - 0.5f * float(side) + 0.5f));
    const int y0 = int(std::floor(py - 0.5f * float(side) + 0.5f));
    if (x0 >= mTarget.width || y0 >= mTarget.height || x0 + side <= 0 || y0 + side <= 0) return;
    ++stats.splats;
    const float depth = z * 0.5f + 0.5f;
    const float a = float(p.rgba >> 24) / 255.0f;
    const float rgb[3] = {float(p.rgba & 0xff) / 255.0f * a, float(p.rgba >> 8 & 0xff) / 255.0f * a,
                          float(p.rgba >> 16 & 0xff) / 255.0f * a};
    for (int yy = std::max(0, y0); yy < std::min(mTarget.height, y0 + side); ++yy)
      for (int xx = std::max(0, x0); xx < std::min(mTarget.width, x0 + side); ++xx) {
        const size_t i = size_t(yy) * mTarget.width + xx;
        if (mOptions.depthTest && depth > mTarget.depth[i]) continue;
        float* dst = &mTarget.rgba[4 * i];
        for (int k = 0; k < 3; ++k) dst[k] = rgb[k] + dst[k] * (1 - a);
        dst[3] = a + dst[3] * (1 - a);
        if (mOptions.depthTest) mTarget.depth[i] = depth;
      }
  }

  glm::vec3 ldiPointOf(uint32_t column, uint32_t row, const DepthPixel& p) const {
    const LdiCamera& c = mLdi.camera;
    return c.origin + (float(column) + 0.5f) * c.pixelSize * c.axisU +
           (float(row) + 0.5f) * c.pixelSize * c.axisV + depthOf(p) * c.direction;
  }

  const Ldi& mLdi;
  ClipBasis mBasis;
  glm::vec3 mEye;
  WarpTarget& mTarget;
  const WarpOptions& mOptions;
  float mDepthStep = 0, mEyeDepth = 0;
  std::vector<size_t> mFirst;
};

// Visits the indices of [0, count) from both ends towards `split` (the epipole): [0, split)
// upwards, then [split, count) downwards.
template <typename Fn>
void towards(int count, int split, Fn&& fn) {
  for (int i = 0; i < split; ++i) fn(i);
  for (int i = count - 1; i >= split; --i) fn(i);
}

}  // namespace

WarpStats warpLdi(const Ldi& ldi, const glm::mat4& tileToClip, const glm::vec3& eyeInTile,
                  WarpTarget& target, const WarpOptions& options) {
  const LdiCamera& c = ldi.camera;
  Splatter splatter(ldi, basisOf(c, tileToClip), eyeInTile, target, options);
  const int width = int(c.width), height = int(c.height);
  if (options.order == WarpOrder::kRowMajor) {
    for (int r = 0; r < height; ++r)
      for (int col = 0; col < width; ++col) splatter.pixel(uint32_t(col), uint32_t(r));
    return splatter.stats;
  }
  // The epipole: the eye projected along the rays onto the image, in pixel coordinates.
  const glm::vec3 e = eyeInTile - c.origin;
  const float ec = glm::dot(e, c.axisU) / c.pixelSize - 0.5f;
  const float er = glm::dot(e, c.axisV) / c.pixelSize - 0.5f;
  const int splitColumn = std::clamp(int(std::floor(ec)) + 1, 0, width);
  const int splitRow = std::clamp(int(std::floor(er)) + 1, 0, height);
  // The four sheets at once: rows towards the epipole's row, in each row columns towards its
  // column (monotone towards the epipole in both, which is all the order needs).
  towards(height, splitRow, [&](int r) {
    towards(width, splitColumn, [&](int col) { splatter.pixel(uint32_t(col), uint32_t(r)); });
  });
  return splatter.stats;
}

}  // namespace terralod::veg
