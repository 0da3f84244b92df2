#include "terralod/measure/image_similarity.h"

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <vector>

namespace terralod {
namespace {

constexpr int kRadius = 5;  // 11 taps
constexpr double kSigma = 1.5;

std::vector<double> luma(const Image& image) {
  std::vector<double> y(size_t(image.width) * size_t(image.height));
  for (size_t i = 0; i < y.size(); ++i) {
    const uint8_t* p = &image.rgba[4 * i];
    y[i] = 0.299 * p[0] + 0.587 * p[1] + 0.114 * p[2];
  }
  return y;
}

// A separable Gaussian blur, the window renormalised where it leaves the image.
std::vector<double> blur(const std::vector<double>& v, int width, int height) {
  std::array<double, 2 * kRadius + 1> w;
  for (int k = -kRadius; k <= kRadius; ++k)
    w[size_t(k + kRadius)] = std::exp(-0.5 * k * k / (kSigma * kSigma));
  std::vector<double> across(v.size()), out(v.size());
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      double sum = 0, weight = 0;
      for (int k = -kRadius; k <= kRadius; ++k) {
        const int xx = x + k;
        if (xx < 0 || xx >= width) continue;
        sum += w[size_t(k + kRadius)] * v[size_t(y) * width + size_t(xx)];
        weight += w[size_t(k + kRadius)];
      }
      across[size_t(y) * width + size_t(x)] = sum / weight;
    }
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      double sum = 0, weight = 0;
      for (int k = -kRadius; k <= kRadius; ++k) {
        const int yy = y + k;
        if (yy < 0 || yy >= height) continue;
        sum += w[size_t(k + kRadius)] * across[size_t(yy) * width + size_t(x)];
        weight += w[size_t(k + kRadius)];
      }
      out[size_t(y) * width + size_t(x)] = sum / weight;
    }
  return out;
}

// Averages f×f blocks (the authors' reference implementation does this first, f =
// max(1, round(min(width, height) / 256)), so that SSIM judges a picture at the scale it is
// seen rather than its pixels' aliasing); a block is counted where most of it is.
struct Reduced {
  int width = 0, height = 0;
  std::vector<double> a, b;
  std::vector<uint8_t> mask;
};

Reduced reduce(const std::vector<double>& a, const std::vector<double>& b,
               std::span<const uint8_t> mask, int width, int height, int f) {
  Reduced r;
  r.width = width / f;
  r.height = height / f;
  r.a.assign(size_t(r.width) * r.height, 0);
  r.b.assign(r.a.size(), 0);
  r.mask.assign(r.a.size(), 1);
  for (int y = 0; y < r.height; ++y)
    for (int x = 0; x < r.width; ++x) {
      double sa = 0, sb = 0;
      int in = 0;
      for (int j = 0; j < f; ++j)
        for (int i = 0; i < f; ++i) {
          const size_t k = size_t(y * f + j) * width + size_t(x * f + i);
          sa += a[k];
          sb += b[k];
          in += mask.empty() || mask[k] != 0;
        }
      const size_t o = size_t(y) * r.width + size_t(x);
      r.a[o] = sa / (f * f);
      r.b[o] = sb / (f * f);
      r.mask[o] = 2 * in > f * f;
    }
  return r;
}

}  // namespace

int similarityScale(int width, int height) {
  return std::max(1, int(std::lround(double(std::min(width, height)) / 256.0)));
}

Similarity structuralSimilarity(const Image& a, const Image& b, std::span<const uint8_t> mask) {
  assert(a.width == b.width && a.height == b.height);
  const int f = similarityScale(a.width, a.height);
  const Reduced r = reduce(luma(a), luma(b), mask, a.width, a.height, f);
  const int w = r.width, h = r.height;
  const std::vector<double>& x = r.a;
  const std::vector<double>& y = r.b;
  mask = r.mask;
  std::vector<double> xx(x.size()), yy(x.size()), xy(x.size());
  for (size_t i = 0; i < x.size(); ++i) {
    xx[i] = x[i] * x[i];
    yy[i] = y[i] * y[i];
    xy[i] = x[i] * y[i];
  }
  const std::vector<double> mx = blur(x, w, h), my = blur(y, w, h);
  const std::vector<double> sxx = blur(xx, w, h), syy = blur(yy, w, h), sxy = blur(xy, w, h);
  constexpr double c1 = (0.01 * 255) * (0.01 * 255), c2 = (0.03 * 255) * (0.03 * 255);
  Similarity s;
  double sum = 0;
  for (size_t i = 0; i < x.size(); ++i) {
    if (!mask.empty() && mask[i] == 0) continue;
    const double vx = sxx[i] - mx[i] * mx[i], vy = syy[i] - my[i] * my[i];
    const double cov = sxy[i] - mx[i] * my[i];
    sum += ((2 * mx[i] * my[i] + c1) * (2 * cov + c2)) /
           ((mx[i] * mx[i] + my[i] * my[i] + c1) * (vx + vy + c2));
    ++s.pixels;
  }
  s.mean = s.pixels ? sum / double(s.pixels) : 1.0;
  return s;
}

}  // namespace terralod
