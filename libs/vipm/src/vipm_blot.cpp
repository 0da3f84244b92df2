#include "terralod/vipm/vipm_blot.h"

#include <algorithm>
#include <cmath>

#include "terralod/core/srgb.h"

namespace terralod {
namespace {

// The splatting shader's output encoding (a pure power law): a fragment's colour is the sum of
// its materials' encoded colours times their weights.
float encode(float linear) {
  return std::pow(std::clamp(linear, 0.0f, 1.0f), 1.0f / 2.2f);
}

}  // namespace

std::array<float, 3> linearMean(std::span<const uint8_t> rgb) {
  std::array<double, 3> sum{};
  for (size_t i = 0; i < rgb.size(); ++i) sum[i % 3] += srgbToLinear(rgb[i]);
  const double n = std::max<double>(1.0, double(rgb.size() / 3));
  return {float(sum[0] / n), float(sum[1] / n), float(sum[2] / n)};
}

std::vector<uint8_t> makeBlotTexels(const ProgressiveMesh& mesh, std::span<const uint8_t> materials,
                                    const MaterialAverages& averages, int32_t texels,
                                    int32_t stride) {
  const int32_t side = texels + 1;
  const int64_t s = stride;
  auto floorDiv = [s](int64_t a) { return a >= 0 ? a / s : -((-a + s - 1) / s); };
  std::vector<std::array<float, 3>> colour(size_t(side) * side, {0.0f, 0.0f, 0.0f});
  auto averageOf = [&](uint16_t v) {
    const uint8_t m = materials[v];
    if (m >= averages.size()) return std::array<float, 3>{0.0f, 0.0f, 0.0f};
    return std::array<float, 3>{encode(averages[m][0]), encode(averages[m][1]),
                                encode(averages[m][2])};
  };
  for (const auto& t : mesh.triangles) {
    std::array<int64_t, 3> x{}, y{};
    for (int k = 0; k < 3; ++k) {
      x[size_t(k)] = int64_t(mesh.points[t[size_t(k)]]) % mesh.width;
      y[size_t(k)] = int64_t(mesh.points[t[size_t(k)]]) / mesh.width;
    }
    const int64_t area = (x[1] - x[0]) * (y[2] - y[0]) - (y[1] - y[0]) * (x[2] - x[0]);
    if (area == 0) continue;
    // The texels whose grid points the triangle's box holds.
    const int64_t x0 = -floorDiv(-std::min({x[0], x[1], x[2]})),
                  x1 = floorDiv(std::max({x[0], x[1], x[2]}));
    const int64_t y0 = -floorDiv(-std::min({y[0], y[1], y[2]})),
                  y1 = floorDiv(std::max({y[0], y[1], y[2]}));
    const std::array<std::array<float, 3>, 3> c{averageOf(t[0]), averageOf(t[1]), averageOf(t[2])};
    for (int64_t ty = y0; ty <= y1 && ty < side; ++ty)
      for (int64_t tx = x0; tx <= x1 && tx < side; ++tx) {
        const int64_t px = tx * s, py = ty * s;
        // Barycentric weights from integer edge functions (points on an edge are inside).
        const int64_t w0 = (x[2] - x[1]) * (py - y[1]) - (y[2] - y[1]) * (px - x[1]);
        const int64_t w1 = (x[0] - x[2]) * (py - y[2]) - (y[0] - y[2]) * (px - x[2]);
        const int64_t w2 = (x[1] - x[0]) * (py - y[0]) - (y[1] - y[0]) * (px - x[0]);
        if ((area > 0 && (w0 < 0 || w1 < 0 || w2 < 0)) ||
            (area < 0 && (w0 > 0 || w1 > 0 || w2 > 0)))
          continue;
        const size_t i = size_t(ty) * size_t(side) + size_t(tx);
        for (int k = 0; k < 3; ++k)
          colour[i][size_t(k)] = (float(w0) * c[0][size_t(k)] + float(w1) * c[1][size_t(k)] +
                                  float(w2) * c[2][size_t(k)]) /
                                 float(area);
      }
  }
  // Outside the data (chunks on its east and north edges): the nearest point inside.
  std::vector<uint8_t> out(colour.size() * 4);
  for (int32_t py = 0; py < side; ++py)
    for (int32_t px = 0; px < side; ++px) {
      const int32_t sx = std::min(px, (mesh.width - 1) / stride);
      const int32_t sy = std::min(py, (mesh.height - 1) / stride);
      const size_t from = size_t(sy) * size_t(side) + size_t(sx);
      const size_t to = (size_t(py) * size_t(side) + size_t(px)) * 4;
      for (int k = 0; k < 3; ++k)
        out[to + size_t(k)] =
            uint8_t(std::lround(255.0f * std::clamp(colour[from][size_t(k)], 0.0f, 1.0f)));
      out[to + 3] = 255;
    }
  return out;
}

}  // namespace terralod
