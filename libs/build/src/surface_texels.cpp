#include "terralod/build/surface_texels.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "terralod/build/height_source.h"
#include "terralod/raster/image_drape.h"

namespace terralod {
namespace {

constexpr int32_t kReliefRadius = BlockTexels::kMargin - 1;

struct Rgb {
  float r, g, b;
};
Rgb mix(Rgb a, Rgb b, float t) {
  return {a.r + (b.r - a.r) * t, a.g + (b.g - a.g) * t, a.b + (b.b - a.b) * t};
}
float smoothstep(float e0, float e1, float x) {
  const float t = std::clamp((x - e0) / (e1 - e0), 0.0f, 1.0f);
  return t * t * (3 - 2 * t);
}

// Display-value (gamma 2.2) colour of ground at relative height t, slope 1 - nz.
Rgb ramp(float t, float slope) {
  const Rgb lowland{0.579f, 0.695f, 0.504f}, hills{0.762f, 0.762f, 0.606f};
  const Rgb rock{0.743f, 0.689f, 0.644f}, snow{0.968f, 0.972f, 0.982f},
      bare{0.695f, 0.667f, 0.644f};
  Rgb c = t < 0.35f   ? mix(lowland, hills, t / 0.35f)
          : t < 0.75f ? mix(hills, rock, (t - 0.35f) / 0.40f)
                      : mix(rock, snow, smoothstep(0.82f, 0.95f, t));
  // Steep ground is bare rock at any height; snow does not hold on it.
  return mix(c, bare, smoothstep(0.45f, 0.75f, slope));
}

// Linear light to display values (gamma 2.2), by table: pow() per texel is a build hot spot.
float toDisplay(float linear) {
  static const std::vector<float> table = [] {
    std::vector<float> t(4097);
    for (size_t i = 0; i < t.size(); ++i) t[i] = std::pow(float(i) / 4096.0f, 1.0f / 2.2f);
    return t;
  }();
  const float x = std::clamp(linear, 0.0f, 1.0f) * 4096.0f;
  const size_t i = std::min<size_t>(size_t(x), 4095);
  return table[i] + (table[i + 1] - table[i]) * (x - float(i));
}

}  // namespace

Status BlockTexels::load(HeightWindows& heights, unsigned worker, const ImageDrape* image,
                         int32_t x0, int32_t y0, int32_t cells) {
  mX0 = x0 - kMargin;
  mY0 = y0 - kMargin;
  mSide = cells + 1 + 2 * kMargin;
  mHeights.resize(size_t(mSide) * mSide);
  if (Status s = heights.read(mX0, mY0, mSide, mSide, mHeights.data(), worker); !s) return s;
  mSums.assign(size_t(mSide + 1) * (mSide + 1), 0.0);
  for (int32_t y = 0; y < mSide; ++y) {
    double row = 0;
    for (int32_t x = 0; x < mSide; ++x) {
      row += mHeights[size_t(y) * mSide + x];
      mSums[size_t(y + 1) * (mSide + 1) + x + 1] = mSums[size_t(y) * (mSide + 1) + x + 1] + row;
    }
  }
  mRefine = 0;
  if (image) {
    mRefine = image->refine();
    mImageX0 = int64_t(x0) * mRefine;
    mImageY0 = int64_t(y0) * mRefine;
    mImageSide = cells * int32_t(mRefine) + 1;
    mImage.resize(size_t(mImageSide) * mImageSide * 4);
    if (Status s = image->read(mImageX0, mImageY0, mImageSide, mImageSide, mImage.data()); !s)
      return s;
  }
  return {};
}

TexelTile BlockTexels::normals(int32_t x0, int32_t y0, int32_t cells) const {
  TexelTile tile(uint32_t(cells + 1), 3);
  const float ix = float(0.5 / mOptions.spacingX), iy = float(0.5 / mOptions.spacingY);
  for (int32_t j = 0; j <= cells; ++j)
    for (int32_t i = 0; i <= cells; ++i) {
      const int32_t gx = x0 + i, gy = y0 + j;
      const float dx = (height(gx + 1, gy) - height(gx - 1, gy)) * ix;
      const float dy = (height(gx, gy + 1) - height(gx, gy - 1)) * iy;
      const float inv = 1.0f / std::sqrt(dx * dx + dy * dy + 1.0f);
      float* n = tile.at(uint32_t(i), uint32_t(j));
      n[0] = -dx * inv;
      n[1] = -dy * inv;
      n[2] = inv;
    }
  return tile;
}

void BlockTexels::generatedColor(int32_t gx, int32_t gy, float* rgb) const {
  const float h = height(gx, gy);
  const float dx = (height(gx + 1, gy) - height(gx - 1, gy)) * float(0.5 / mOptions.spacingX);
  const float dy = (height(gx, gy + 1) - height(gx, gy - 1)) * float(0.5 / mOptions.spacingY);
  const float nz = 1.0f / std::sqrt(dx * dx + dy * dy + 1.0f);
  const double range = std::max(mOptions.zMax - mOptions.zMin, 1e-3);
  Rgb c = ramp(float(std::clamp((h - mOptions.zMin) / range, 0.0, 1.0)), 1.0f - nz);
  // Hollows (below the mean of their surroundings) see less sky: a baked occlusion term.
  const int32_t r = kReliefRadius;
  const int32_t lx0 = gx - mX0 - r, ly0 = gy - mY0 - r, lx1 = gx - mX0 + r + 1,
                ly1 = gy - mY0 + r + 1;
  const size_t w = size_t(mSide + 1);
  const double sum = mSums[size_t(ly1) * w + lx1] - mSums[size_t(ly0) * w + lx1] -
                     mSums[size_t(ly1) * w + lx0] + mSums[size_t(ly0) * w + lx0];
  const double mean = sum / double((2 * r + 1) * (2 * r + 1));
  const double scale = r * std::max(mOptions.spacingX, mOptions.spacingY);
  const float occlusion = float(std::clamp(1.0 + 0.8 * (h - mean) / scale, 0.6, 1.0));
  // Stored as display values: darkening linear light by `occlusion` scales display values by
  // occlusion^(1/2.2).
  const float shade = toDisplay(occlusion);
  rgb[0] = c.r * shade;
  rgb[1] = c.g * shade;
  rgb[2] = c.b * shade;
}

TexelTile BlockTexels::colors(int32_t x0, int32_t y0, int32_t cells) const {
  TexelTile generated(uint32_t(cells + 1), 3);
  for (int32_t j = 0; j <= cells; ++j)
    for (int32_t i = 0; i <= cells; ++i)
      generatedColor(x0 + i, y0 + j, generated.at(uint32_t(i), uint32_t(j)));
  if (mRefine == 0) return generated;
  const uint32_t size = uint32_t(cells) * mRefine + 1;
  TexelTile fallback = resampleTile(generated, size);
  TexelTile tile(size, 3);
  const int64_t fx0 = int64_t(x0) * mRefine - mImageX0, fy0 = int64_t(y0) * mRefine - mImageY0;
  for (uint32_t j = 0; j < size; ++j)
    for (uint32_t i = 0; i < size; ++i) {
      const uint8_t* p = mImage.data() + (size_t(fy0 + j) * mImageSide + size_t(fx0 + i)) * 4;
      const float a = p[3] / 255.0f;
      const float* g = fallback.at(i, j);
      float* out = tile.at(i, j);
      for (int c = 0; c < 3; ++c) out[c] = a * (p[c] / 255.0f) + (1 - a) * g[c];
    }
  return tile;
}

}  // namespace terralod
