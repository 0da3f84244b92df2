#include "terralod/vipm/vipm_normal_map.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace terralod {

std::vector<float> finestGridHeights(const ProgressiveMesh& mesh,
                                     std::span<const std::array<float, 3>> positions) {
  const int32_t w = mesh.width, h = mesh.height;
  std::vector<float> heights(size_t(w) * size_t(h), std::numeric_limits<float>::quiet_NaN());
  for (const auto& tri : mesh.triangles) {
    // Integer corners: exact edge functions; every grid point inside or on the triangle.
    std::array<int64_t, 3> xs, ys;
    std::array<double, 3> zs;
    for (int k = 0; k < 3; ++k) {
      xs[size_t(k)] = mesh.points[tri[size_t(k)]] % w;
      ys[size_t(k)] = mesh.points[tri[size_t(k)]] / w;
      zs[size_t(k)] = positions[tri[size_t(k)]][2];
    }
    const int64_t area = (xs[1] - xs[0]) * (ys[2] - ys[0]) - (xs[2] - xs[0]) * (ys[1] - ys[0]);
    if (area == 0) continue;
    const int64_t sign = area > 0 ? 1 : -1;
    const auto [x0, x1] = std::minmax({xs[0], xs[1], xs[2]});
    const auto [y0, y1] = std::minmax({ys[0], ys[1], ys[2]});
    for (int64_t y = y0; y <= y1; ++y)
      for (int64_t x = x0; x <= x1; ++x) {
        std::array<int64_t, 3> b;
        for (int k = 0; k < 3; ++k) {
          const size_t i = size_t(k), j = size_t((k + 1) % 3), o = size_t((k + 2) % 3);
          b[o] = sign * ((xs[j] - xs[i]) * (y - ys[i]) - (ys[j] - ys[i]) * (x - xs[i]));
        }
        if (b[0] < 0 || b[1] < 0 || b[2] < 0) continue;
        const double z = (double(b[0]) * zs[0] + double(b[1]) * zs[1] + double(b[2]) * zs[2]) /
                         double(sign * area);
        heights[size_t(y) * size_t(w) + size_t(x)] = float(z);
      }
  }
  // Stored vertices exactly as stored (a plane through them gives them back up to rounding).
  for (uint32_t v = 0; v < mesh.vertexCount(); ++v) heights[mesh.points[v]] = positions[v][2];
  // A valid mesh covers its rectangle; should a point be left, give it a vertex's height.
  const float fallback = positions.empty() ? 0.0f : positions[0][2];
  for (float& z : heights)
    if (std::isnan(z)) z = fallback;
  return heights;
}

std::vector<uint8_t> normalMap(std::span<const float> heights, int32_t width, int32_t height,
                               std::array<double, 2> spacing) {
  std::vector<uint8_t> out(size_t(width) * size_t(height) * 2);
  auto at = [&](int32_t x, int32_t y) { return double(heights[size_t(y) * size_t(width) + x]); };
  for (int32_t y = 0; y < height; ++y)
    for (int32_t x = 0; x < width; ++x) {
      const int32_t xa = std::max(x - 1, 0), xb = std::min(x + 1, width - 1);
      const int32_t ya = std::max(y - 1, 0), yb = std::min(y + 1, height - 1);
      const double dx = xb > xa ? (at(xb, y) - at(xa, y)) / (double(xb - xa) * spacing[0]) : 0.0;
      const double dy = yb > ya ? (at(x, yb) - at(x, ya)) / (double(yb - ya) * spacing[1]) : 0.0;
      const double len = std::sqrt(dx * dx + dy * dy + 1.0);
      const size_t i = (size_t(y) * size_t(width) + size_t(x)) * 2;
      out[i] = uint8_t(std::lround((-dx / len + 1.0) * 0.5 * 255.0));
      out[i + 1] = uint8_t(std::lround((-dy / len + 1.0) * 0.5 * 255.0));
    }
  return out;
}

}  // namespace terralod
