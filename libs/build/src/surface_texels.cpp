#include "terralod/build/surface_texels.h"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <limits>
#include <vector>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "terralod/build/height_source.h"
#include "terralod/raster/image_drape.h"
#include "terralod/raster/void_fill.h"

namespace terralod {
namespace {

constexpr int32_t kReliefRadius = BlockTexels::kMargin - 1;
static_assert(2 * kWaterRadius <= BlockTexels::kMargin,
              "water windows around the margin's inner samples must lie in the window");

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

// Occlusion from the sum of the heights of the (2r + 1)^2 samples around a sample at `height`.
float occlusionOf(double sum, float height, double area, double scale) {
  const double mean = sum / area;
  return float(std::clamp(1.0 + 0.8 * (height - mean) / scale, double(kMinOcclusion), 1.0));
}

// Each 7-sample window along a row of `side` heights, by its centre (kWaterRadius .. side -
// kWaterRadius - 1): all at sea level (bit 0 of `flags`), and within kLakeFlatness of each
// other (bit 1), with their minimum and maximum (which only windows with bit 1 need). With SSE2
// four windows at a time; the same flags either way (min and max keep their operand order, so
// even NaNs come out as in the scalar loop). Returns whether any window has a flag.
bool rowWindows(const float* h, int32_t side, uint8_t* flags, float* lo, float* hi) {
  const int32_t r = kWaterRadius;
  const float band = float(kSeaLevelBand), flat = float(kLakeFlatness);
  int32_t x = r;
  int any = 0;
#if defined(__SSE2__)
  const __m128 magnitude = _mm_castsi128_ps(_mm_set1_epi32(0x7fffffff)), bands = _mm_set1_ps(band),
               flats = _mm_set1_ps(flat);
  for (; x + 4 <= side - r; x += 4) {
    __m128 v = _mm_loadu_ps(h + x - r);
    __m128 mn = v, mx = v, sea = _mm_cmple_ps(_mm_and_ps(v, magnitude), bands);
    for (int32_t k = -r + 1; k <= r; ++k) {
      v = _mm_loadu_ps(h + x + k);
      mn = _mm_min_ps(v, mn);
      mx = _mm_max_ps(v, mx);
      sea = _mm_and_ps(sea, _mm_cmple_ps(_mm_and_ps(v, magnitude), bands));
    }
    const int seaBits = _mm_movemask_ps(sea),
              lakeBits = _mm_movemask_ps(_mm_cmple_ps(_mm_sub_ps(mx, mn), flats));
    _mm_storeu_ps(lo + x, mn);
    _mm_storeu_ps(hi + x, mx);
    any |= seaBits | lakeBits;
    for (int l = 0; l < 4; ++l)
      flags[x + l] = uint8_t(((seaBits >> l) & 1) | (((lakeBits >> l) & 1) << 1));
  }
#endif
  // Both tests stop at the first sample that fails them, which on land is the first or second.
  for (; x < side - r; ++x) {
    const float* w = h + x;
    uint8_t f = 1;
    for (int32_t k = -r; k <= r && f; ++k)
      if (!(std::fabs(w[k]) <= band)) f = 0;
    float l = w[-r], u = w[-r];
    bool lake = true;
    for (int32_t k = -r + 1; k <= r && lake; ++k) {
      l = std::min(l, w[k]);
      u = std::max(u, w[k]);
      lake = u - l <= flat;
    }
    flags[x] = uint8_t(f | (lake ? 2 : 0));
    any |= flags[x];
    lo[x] = l;
    hi[x] = u;
  }
  return any != 0;
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
  mRowSnowLine.resize(size_t(mSide));
  const std::vector<double>* latitudes = mOptions.rowLatitudes.get();
  for (int32_t y = 0; y < mSide; ++y) {
    const int32_t gy = mY0 + y;
    mRowSnowLine[size_t(y)] =
        float(snowLine(latitudes && !latitudes->empty()
                           ? (*latitudes)[size_t(std::clamp(gy, 0, int32_t(latitudes->size()) - 1))]
                           : kUnknownLatitude));
  }
  findWater();
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

// Water: the union of the 7 x 7 windows that lie inside the data and are flat at sea level or
// exactly flat (min and max by rows, then by columns), and the filled sea voids.
void BlockTexels::findWater() {
  const int32_t side = mSide, r = kWaterRadius;
  mWater.assign(size_t(side) * side, 0);
  auto inside = [](int32_t g, int32_t size) { return size == 0 || (g >= 0 && g < size); };
  mRowFlags.assign(size_t(side) * side, 0);
  mRowMin.resize(size_t(side) * side);
  mRowMax.resize(size_t(side) * side);
  // flagged[y]: how many rows up to y in a row have a flagged window (a window of 7 rows
  // needs 7; on land most have none, and their rows are skipped below).
  std::vector<int32_t> flagged(size_t(side), 0);
  for (int32_t y = 0; y < side; ++y) {
    const size_t row = size_t(y) * side;
    if (rowWindows(mHeights.data() + row, side, mRowFlags.data() + row, mRowMin.data() + row,
                   mRowMax.data() + row))
      flagged[size_t(y)] = y > 0 ? flagged[size_t(y) - 1] + 1 : 1;
  }
  // Windows: 7 rows that are all at sea level, or all flat and together within kLakeFlatness.
  const float flat = float(kLakeFlatness);
  std::vector<uint8_t> core(size_t(side) * side, 0);
  bool any = false;
  for (int32_t y = r; y < side - r; ++y) {
    if (flagged[size_t(y + r)] < 2 * r + 1) continue;
    if (!inside(mY0 + y - r, mOptions.rows) || !inside(mY0 + y + r, mOptions.rows)) continue;
    for (int32_t x = r; x < side - r; ++x) {
      if (!inside(mX0 + x - r, mOptions.columns) || !inside(mX0 + x + r, mOptions.columns))
        continue;
      size_t i = size_t(y - r) * side + x;
      uint8_t f = mRowFlags[i];
      float lo = mRowMin[i], hi = mRowMax[i];
      for (int32_t k = -r + 1; k <= r && f; ++k) {
        i += size_t(side);
        f &= mRowFlags[i];
        if (f & 2) {
          lo = std::min(lo, mRowMin[i]);
          hi = std::max(hi, mRowMax[i]);
          if (!(hi - lo <= flat)) f &= 1;
        }
      }
      if (f) {
        core[size_t(y) * side + x] = 1;
        any = true;
      }
    }
  }
  if (any) {
    // Dilate the window centres into whole windows: by rows, then by columns.
    std::vector<uint8_t> rows(size_t(side) * side, 0);
    for (int32_t y = 0; y < side; ++y)
      for (int32_t x = r; x < side - r; ++x) {
        const uint8_t* c = core.data() + size_t(y) * side + x;
        uint8_t v = 0;
        for (int32_t k = -r; k <= r; ++k) v |= c[k];
        rows[size_t(y) * side + x] = v;
      }
    for (int32_t y = r; y < side - r; ++y)
      for (int32_t x = 0; x < side; ++x) {
        uint8_t v = 0;
        for (int32_t k = -r; k <= r; ++k) v |= rows[size_t(y + k) * side + x];
        mWater[size_t(y) * side + x] = v;
      }
  }
  if (const SampleMask* sea = mOptions.seaVoids.get())
    for (int32_t y = 0; y < side; ++y)
      for (int32_t x = 0; x < side; ++x)
        if (sea->at(mX0 + x, mY0 + y)) mWater[size_t(y) * side + x] = 1;
}

// centralDifferenceNormals over the window's rows; with SSE2 four texels at a time, by the same
// operations in the same order as normalFromSlopes.
TexelTile BlockTexels::normals(int32_t x0, int32_t y0, int32_t cells) const {
  TexelTile tile(uint32_t(cells + 1), 3);
  const float ix = float(0.5 / mOptions.spacingX), iy = float(0.5 / mOptions.spacingY);
  for (int32_t j = 0; j <= cells; ++j) {
    const float* h = mHeights.data() + size_t(y0 + j - mY0) * mSide + (x0 - mX0);
    const float *south = h - mSide, *north = h + mSide;
    float* out = tile.at(0, uint32_t(j));
    int32_t i = 0;
#if defined(__SSE2__)
    for (; i + 4 <= cells + 1; i += 4) {
      const __m128 dx =
          _mm_mul_ps(_mm_sub_ps(_mm_loadu_ps(h + i + 1), _mm_loadu_ps(h + i - 1)), _mm_set1_ps(ix));
      const __m128 dy =
          _mm_mul_ps(_mm_sub_ps(_mm_loadu_ps(north + i), _mm_loadu_ps(south + i)), _mm_set1_ps(iy));
      const __m128 inv =
          _mm_div_ps(_mm_set1_ps(1.0f),
                     _mm_sqrt_ps(_mm_add_ps(_mm_add_ps(_mm_mul_ps(dx, dx), _mm_mul_ps(dy, dy)),
                                            _mm_set1_ps(1.0f))));
      const __m128 sign = _mm_set1_ps(-0.0f);
      float nx[4], ny[4], nz[4];
      _mm_storeu_ps(nx, _mm_mul_ps(_mm_xor_ps(dx, sign), inv));
      _mm_storeu_ps(ny, _mm_mul_ps(_mm_xor_ps(dy, sign), inv));
      _mm_storeu_ps(nz, inv);
      for (int l = 0; l < 4; ++l) {
        out[3 * (i + l)] = nx[l];
        out[3 * (i + l) + 1] = ny[l];
        out[3 * (i + l) + 2] = nz[l];
      }
    }
#endif
    for (; i <= cells; ++i)
      normalFromSlopes((h[i + 1] - h[i - 1]) * ix, (north[i] - south[i]) * iy, out + 3 * i);
  }
  return tile;
}

// Hollows (below the mean of their surroundings) see less sky: a baked occlusion term.
float BlockTexels::occlusion(int32_t gx, int32_t gy) const {
  const int32_t r = kReliefRadius;
  const int32_t lx0 = gx - mX0 - r, ly0 = gy - mY0 - r, lx1 = gx - mX0 + r + 1,
                ly1 = gy - mY0 + r + 1;
  const size_t w = size_t(mSide + 1);
  const double sum = mSums[size_t(ly1) * w + lx1] - mSums[size_t(ly0) * w + lx1] -
                     mSums[size_t(ly1) * w + lx0] + mSums[size_t(ly0) * w + lx0];
  return occlusionOf(sum, height(gx, gy), double((2 * r + 1) * (2 * r + 1)),
                     r * std::max(mOptions.spacingX, mOptions.spacingY));
}

void BlockTexels::generatedColor(int32_t gx, int32_t gy, float* rgb) const {
  if (water(gx, gy)) {
    rgb[0] = kWaterColor.r;
    rgb[1] = kWaterColor.g;
    rgb[2] = kWaterColor.b;
    return;
  }
  const int32_t ly = gy - mY0;
  const float h = height(gx, gy);
  const float dx = (height(gx + 1, gy) - height(gx - 1, gy)) * float(0.5 / mOptions.spacingX);
  const float dy = (height(gx, gy + 1) - height(gx, gy - 1)) * float(0.5 / mOptions.spacingY);
  const float nz = 1.0f / std::sqrt(dx * dx + dy * dy + 1.0f);
  const GroundColor c = groundColorBelow(h, 1.0f - nz, mRowSnowLine[size_t(ly)]);
  // Stored as display values: darkening linear light by the occlusion scales display values
  // by occlusion^(1/2.2).
  const float shade = toDisplay(occlusion(gx, gy));
  rgb[0] = c.r * shade;
  rgb[1] = c.g * shade;
  rgb[2] = c.b * shade;
}

// occlusion() and water() of every texel, a row at a time.
TexelTile BlockTexels::shades(int32_t x0, int32_t y0, int32_t cells) const {
  TexelTile tile(uint32_t(cells + 1), 1);
  const int32_t r = kReliefRadius;
  const size_t w = size_t(mSide + 1);
  const double area = double((2 * r + 1) * (2 * r + 1)),
               scale = r * std::max(mOptions.spacingX, mOptions.spacingY);
  for (int32_t j = 0; j <= cells; ++j) {
    const int32_t ly = y0 + j - mY0, lx = x0 - mX0;
    const float* h = mHeights.data() + size_t(ly) * mSide + lx;
    const uint8_t* water = mWater.data() + size_t(ly) * mSide + lx;
    // Summed-area rows above and below the window, at the window's west edge.
    const double* above = mSums.data() + size_t(ly + r + 1) * w + (lx - r);
    const double* below = mSums.data() + size_t(ly - r) * w + (lx - r);
    float* out = tile.at(0, uint32_t(j));
    int32_t i = 0;
#if defined(__SSE2__)
    // Two texels at a time, by the same operations in the same order as occlusionOf and
    // shadeValue (the divisions are most of the time, and SSE2 does two at once).
    for (; i + 2 <= cells + 1; i += 2) {
      const int32_t e = i + 2 * r + 1;
      const __m128d sum =
          _mm_add_pd(_mm_sub_pd(_mm_sub_pd(_mm_loadu_pd(above + e), _mm_loadu_pd(below + e)),
                                _mm_loadu_pd(above + i)),
                     _mm_loadu_pd(below + i));
      const __m128d mean = _mm_div_pd(sum, _mm_set1_pd(area));
      const __m128d height = _mm_cvtps_pd(_mm_setr_ps(h[i], h[i + 1], 0.0f, 0.0f));
      const __m128d relief =
          _mm_div_pd(_mm_mul_pd(_mm_set1_pd(0.8), _mm_sub_pd(height, mean)), _mm_set1_pd(scale));
      const __m128d occlusion = _mm_min_pd(
          _mm_set1_pd(1.0),
          _mm_max_pd(_mm_set1_pd(double(kMinOcclusion)), _mm_add_pd(_mm_set1_pd(1.0), relief)));
      const __m128 t = _mm_div_ps(_mm_sub_ps(_mm_cvtpd_ps(occlusion), _mm_set1_ps(kMinOcclusion)),
                                  _mm_set1_ps(1.0f - kMinOcclusion));
      const __m128 shade =
          _mm_add_ps(_mm_set1_ps(kLandShade),
                     _mm_mul_ps(_mm_set1_ps(1.0f - kLandShade),
                                _mm_min_ps(_mm_set1_ps(1.0f), _mm_max_ps(_mm_setzero_ps(), t))));
      float two[4];
      _mm_storeu_ps(two, shade);
      out[i] = water[i] ? shadeValue(true, 1.0f) : two[0];
      out[i + 1] = water[i + 1] ? shadeValue(true, 1.0f) : two[1];
    }
#endif
    for (; i <= cells; ++i) {
      if (water[i]) {
        out[i] = shadeValue(true, 1.0f);
        continue;
      }
      const int32_t e = i + 2 * r + 1;
      const double sum = above[e] - below[e] - above[i] + below[i];
      out[i] = shadeValue(false, occlusionOf(sum, h[i], area, scale));
    }
  }
  return tile;
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
