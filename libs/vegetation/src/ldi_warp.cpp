#include "terralod/vegetation/ldi_warp.h"

#include <algorithm>
#include <array>
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

// Per warp, what every depth pixel shares: the clip basis, the half test as an affine function
// of (column, row, depth), the splat footprint's scale and a table of the normal's effect per
// splat index, so a depth pixel costs a few multiply-adds, one division and a table look-up.
class Splatter {
 public:
  Splatter(const WarpLdi& ldi, const ClipBasis& basis, const std::optional<ClipBasis>& northWest,
           const glm::vec3& eye, WarpTarget& target, const WarpOptions& options)
      : mLdi(ldi.ldi),
        mRowFirst(ldi.rowStarts),
        mBasis(basis),
        mNorthWest(northWest),
        mTarget(target),
        mOptions(options) {
    const LdiCamera& c = mLdi.camera;
    mDepthStep = (c.depthMax - c.depthMin) / float(kLdiMaxDepth);
    mEyeDepth = glm::dot(eye, c.direction);
    mEyeQuantized = (mEyeDepth - c.depthMin) / mDepthStep;
    // x − y of a depth pixel's point in the tile frame (halfOf: x ≥ y is the south-east half).
    const glm::vec3 diagonal(1, -1, 0);
    const glm::vec3 first = c.origin + 0.5f * c.pixelSize * (c.axisU + c.axisV);
    mHalf = {glm::dot(first + c.depthMin * c.direction, diagonal),
             c.pixelSize * glm::dot(c.axisU, diagonal), c.pixelSize * glm::dot(c.axisV, diagonal),
             mDepthStep * glm::dot(c.direction, diagonal)};
    if (options.sizedSplats) {
      // The footprint of an LDI pixel at the LDI's centre, in target pixels times w: it
      // scales as 1/w over the tile.
      const glm::vec3 centre = first + 0.5f * c.pixelSize * float(c.width - 1) * c.axisU +
                               0.5f * c.pixelSize * float(c.height - 1) * c.axisV +
                               0.5f * (c.depthMin + c.depthMax) * c.direction;
      const glm::vec4 clip = basis.base + centreClipOffset(c, centre - first);
      mFootprint = clip.w > 1e-6f ? std::max(pixelsMoved(clip, basis.column, target),
                                             pixelsMoved(clip, basis.row, target)) *
                                        clip.w
                                  : 0.0f;
      mToEye = glm::normalize(eye - centre);
    }
  }

  // Draws row `row`'s pixels from both ends towards column `split` (the epipole's).
  void row(uint32_t row, uint32_t split) {
    const uint32_t width = mLdi.camera.width;
    const uint8_t* counts = &mLdi.layerCounts[size_t(row) * width];
    size_t at = mRowFirst[row];
    for (uint32_t col = 0; col < split; ++col) {
      const size_t next = at + counts[col];
      if (next != at) pixel(col, row, at, next);
      at = next;
    }
    at = mRowFirst[row + 1];
    for (uint32_t col = width; col-- > split;) {
      const size_t before = at - counts[col];
      if (before != at) pixel(col, row, before, at);
      at = before;
    }
  }

  // Draws pixel (column, row)'s layers [lo, hi), those farther from the eye along the rays
  // first.
  void pixel(uint32_t column, uint32_t row, size_t lo, size_t hi) {
    const glm::vec4 at = mBasis.base + float(column) * mBasis.column + float(row) * mBasis.row;
    const glm::vec4 atNorthWest =
        mNorthWest
            ? mNorthWest->base + float(column) * mNorthWest->column + float(row) * mNorthWest->row
            : at;
    const float halfAt = mHalf[0] + float(column) * mHalf[1] + float(row) * mHalf[2];
    const DepthPixel* p = mLdi.pixels.data();
    if (mOptions.order == WarpOrder::kRowMajor) {
      for (size_t k = lo; k < hi; ++k) layer(at, atNorthWest, halfAt, p[k]);
      return;
    }
    // Layers are stored front first; draw those farther from the eye along the rays first.
    if (float(p[lo].depth()) >= mEyeQuantized) {  // the eye in front of them all
      for (size_t k = hi; k-- > lo;) layer(at, atNorthWest, halfAt, p[k]);
      return;
    }
    if (float(p[hi - 1].depth()) <= mEyeQuantized) {  // behind them all
      for (size_t k = lo; k < hi; ++k) layer(at, atNorthWest, halfAt, p[k]);
      return;
    }
    while (lo < hi) {  // among them: from both ends
      const float front = std::abs(float(p[lo].depth()) - mEyeQuantized);
      const float back = std::abs(float(p[hi - 1].depth()) - mEyeQuantized);
      if (back >= front)
        layer(at, atNorthWest, halfAt, p[--hi]);
      else
        layer(at, atNorthWest, halfAt, p[lo++]);
    }
  }

  WarpStats stats;

 private:
  // The clip position of a tile-frame offset from the first pixel's centre on the image plane.
  glm::vec4 centreClipOffset(const LdiCamera& c, const glm::vec3& offset) const {
    return glm::dot(offset, c.axisU) / c.pixelSize * mBasis.column +
           glm::dot(offset, c.axisV) / c.pixelSize * mBasis.row +
           glm::dot(offset, c.direction) * mBasis.depth;
  }

  void layer(const glm::vec4& at, const glm::vec4& atNorthWest, float halfAt, const DepthPixel& p) {
    ++stats.depthPixels;
    const float quantized = float(p.depth());
    const float depthAlong = mLdi.camera.depthMin + quantized * mDepthStep;
    glm::vec4 clip;
    if (mOptions.onlyHalf || mNorthWest) {
      const bool southEast = halfAt + quantized * mHalf[3] >= 0.0f;
      if (mOptions.onlyHalf && southEast != (*mOptions.onlyHalf == TileHalf::kSouthEast)) return;
      clip = southEast || !mNorthWest ? at + depthAlong * mBasis.depth
                                      : atNorthWest + depthAlong * mNorthWest->depth;
    } else {
      clip = at + depthAlong * mBasis.depth;
    }
    if (clip.w <= 1e-6f) return;  // behind the eye
    const float invW = 1.0f / clip.w;
    const float x = clip.x * invW, y = clip.y * invW, z = clip.z * invW;
    if (z < -1 || z > 1) return;
    const float px = (x * 0.5f + 0.5f) * float(mTarget.width);
    const float py = (0.5f - y * 0.5f) * float(mTarget.height);
    int side = 1;
    if (mOptions.sizedSplats) {
      float size = mFootprint * invW;
      // The normal's factor is at most √2: below 1/√2 pixels the splat is one pixel anyway.
      if (size > 0.7f) size *= normalFactor(std::min(p.splat(), kLdiMaxSplatCode));
      side = std::clamp(int(std::ceil(size - 0.01f)), 1, mOptions.maxSplat);  // 1.0001 is 1
    }
    const int x0 = int(std::floor(px - 0.5f * float(side) + 0.5f));
    const int y0 = int(std::floor(py - 0.5f * float(side) + 0.5f));
    if (x0 >= mTarget.width || y0 >= mTarget.height || x0 + side <= 0 || y0 + side <= 0) return;
    ++stats.splats;
    const float depth = z * 0.5f + 0.5f;
    const float a = float(p.rgba >> 24) * (mOptions.opacity / 255.0f);
    const float scale = a * (1.0f / 255.0f);
    const float rgb[3] = {float(p.rgba & 0xff) * scale, float(p.rgba >> 8 & 0xff) * scale,
                          float(p.rgba >> 16 & 0xff) * scale};
    // Only what mostly covers its pixel hides what lies behind: a faint splat (a fading
    // LDI's, a surface's ragged edge) written into the depth would hide the solid surface a
    // little behind it.
    const bool writesDepth = mOptions.depthTest && a >= 0.5f;
    const int yBegin = std::max(0, y0), yEnd = std::min(mTarget.height, y0 + side);
    const int xBegin = std::max(0, x0), xEnd = std::min(mTarget.width, x0 + side);
    mTarget.dirtyTop = std::min(mTarget.dirtyTop, yBegin);
    mTarget.dirtyBottom = std::max(mTarget.dirtyBottom, yEnd);
    for (int yy = yBegin; yy < yEnd; ++yy)
      for (int xx = xBegin; xx < xEnd; ++xx) {
        const size_t i = size_t(yy) * mTarget.width + xx;
        if (mOptions.depthTest && depth > mTarget.depth[i]) continue;
        float* dst = &mTarget.rgba[4 * i];
        for (int k = 0; k < 3; ++k) dst[k] = rgb[k] + dst[k] * (1 - a);
        dst[3] = a + dst[3] * (1 - a);
        if (writesDepth) mTarget.depth[i] = depth;
      }
  }

  // How obliquely the LDI saw a surface against how squarely the eye sees it, per splat index
  // (made on first use: far tiles never need it).
  float normalFactor(uint32_t splat) {
    if (mNormalFactor.empty()) {
      const std::vector<glm::vec3>& normals = splatNormals();
      mNormalFactor.resize(normals.size());
      for (size_t k = 0; k < normals.size(); ++k) {
        const float seenByLdi =
            std::max(0.3f, std::abs(glm::dot(normals[k], mLdi.camera.direction)));
        mNormalFactor[k] =
            std::sqrt(std::clamp(std::abs(glm::dot(normals[k], mToEye)) / seenByLdi, 0.5f, 2.0f));
      }
    }
    return mNormalFactor[splat];
  }

  static const std::vector<glm::vec3>& splatNormals() {
    static const std::vector<glm::vec3> normals = [] {
      std::vector<glm::vec3> n(kLdiMaxSplatCode + 1);
      for (uint32_t k = 0; k <= kLdiMaxSplatCode; ++k) n[k] = decodeSplatNormal(k);
      return n;
    }();
    return normals;
  }

  const Ldi& mLdi;
  const std::vector<uint64_t>& mRowFirst;
  ClipBasis mBasis;
  std::optional<ClipBasis> mNorthWest;
  WarpTarget& mTarget;
  const WarpOptions& mOptions;
  float mDepthStep = 0, mEyeDepth = 0, mEyeQuantized = 0;
  std::array<float, 4> mHalf{};  // x − y: base, per column, per row, per quantized depth
  float mFootprint = 0;
  glm::vec3 mToEye{0, 0, 1};
  std::vector<float> mNormalFactor;
};

}  // namespace

uint32_t packRgba8(const float* c) {
  const auto byte = [](float v) { return uint32_t(std::clamp(v, 0.0f, 1.0f) * 255.0f + 0.5f); };
  return byte(c[0]) | byte(c[1]) << 8 | byte(c[2]) << 16 | byte(c[3]) << 24;
}

void WarpTarget::clear() {
  if (dirtyTop < dirtyBottom) {
    const size_t first = size_t(dirtyTop) * size_t(width),
                 last = size_t(dirtyBottom) * size_t(width);
    std::fill(rgba.begin() + ptrdiff_t(4 * first), rgba.begin() + ptrdiff_t(4 * last), 0.0f);
    std::fill(depth.begin() + ptrdiff_t(first), depth.begin() + ptrdiff_t(last), 1.0f);
  }
  dirtyTop = height;
  dirtyBottom = 0;
}

WarpLdi WarpLdi::of(Ldi ldi) {
  WarpLdi w;
  w.rowStarts.assign(ldi.camera.height + 1, 0);
  for (uint32_t r = 0; r < ldi.camera.height; ++r) {
    uint64_t n = 0;
    for (uint32_t col = 0; col < ldi.camera.width; ++col)
      n += ldi.layerCounts[size_t(r) * ldi.camera.width + col];
    w.rowStarts[r + 1] = w.rowStarts[r] + n;
  }
  w.ldi = std::move(ldi);
  return w;
}

WarpStats warpLdi(const Ldi& ldi, const glm::mat4& tileToClip, const glm::vec3& eyeInTile,
                  WarpTarget& target, const WarpOptions& options) {
  return warpLdi(WarpLdi::of(ldi), tileToClip, eyeInTile, target, options);
}

WarpStats warpLdi(const WarpLdi& warpable, const glm::mat4& tileToClip, const glm::vec3& eyeInTile,
                  WarpTarget& target, const WarpOptions& options) {
  const LdiCamera& c = warpable.ldi.camera;
  std::optional<ClipBasis> northWest;
  if (options.northWestToClip) northWest = basisOf(c, *options.northWestToClip);
  Splatter splatter(warpable, basisOf(c, tileToClip), northWest, eyeInTile, target, options);
  const int width = int(c.width), height = int(c.height);
  if (options.order == WarpOrder::kRowMajor) {
    for (int r = 0; r < height; ++r) splatter.row(uint32_t(r), uint32_t(width));
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
  for (int r = 0; r < splitRow; ++r) splatter.row(uint32_t(r), uint32_t(splitColumn));
  for (int r = height - 1; r >= splitRow; --r) splatter.row(uint32_t(r), uint32_t(splitColumn));
  return splatter.stats;
}

}  // namespace terralod::veg
