#include "terralod/vegetation/ldi_camera.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <numbers>

#include <glm/geometric.hpp>

namespace terralod::veg {

std::array<float, kRings> ringDistancesFor(float tileSize,
                                           const std::array<uint32_t, kRings>& resolutions) {
  std::array<float, kRings> d{};
  for (int r = 0; r < kRings; ++r) d[r] = tileSize * float(resolutions[0]) / float(resolutions[r]);
  return d;
}

void scaleResolutions(LdiRig& rig, uint32_t finest) {
  const double scale = double(finest) / double(kPaperResolutions[0]);
  for (int r = 0; r < kRings; ++r)
    rig.resolutions[r] = std::max(4u, uint32_t(std::lround(kPaperResolutions[r] * scale)));
  rig.ringDistances = ringDistancesFor(rig.tileSize, rig.resolutions);
}

float ringElevation(const LdiRig& rig, int ring) {
  return std::atan2(rig.headHeight, rig.ringDistances[ring]);
}

float directionAzimuth(int direction) {
  return float(direction) * float(std::numbers::pi) / 4.0f;
}

LdiCamera ldiCamera(const LdiRig& rig, int ring, int direction) {
  assert(ring >= 0 && ring < kRings && direction >= 0 && direction < kDirections);
  const float az = directionAzimuth(direction), el = ringElevation(rig, ring);
  LdiCamera c;
  c.direction = {std::sin(az) * std::cos(el), std::cos(az) * std::cos(el), -std::sin(el)};
  c.axisU = {std::cos(az), -std::sin(az), 0};  // to the viewer's right
  c.axisV = glm::cross(c.axisU, c.direction);  // up on the image
  float lo[3] = {1e30f, 1e30f, 1e30f}, hi[3] = {-1e30f, -1e30f, -1e30f};
  for (int k = 0; k < 8; ++k) {
    const glm::vec3 p{k & 1 ? rig.tileSize : 0, k & 2 ? rig.tileSize : 0,
                      k & 4 ? rig.tileHeight : 0};
    const float q[3] = {glm::dot(p, c.axisU), glm::dot(p, c.axisV), glm::dot(p, c.direction)};
    for (int i = 0; i < 3; ++i) lo[i] = std::min(lo[i], q[i]), hi[i] = std::max(hi[i], q[i]);
  }
  const float extent = std::max(hi[0] - lo[0], hi[1] - lo[1]);
  c.pixelSize = extent / float(rig.resolutions[ring]);
  c.width = std::max(1u, uint32_t(std::ceil((hi[0] - lo[0]) / c.pixelSize - 1e-4f)));
  c.height = std::max(1u, uint32_t(std::ceil((hi[1] - lo[1]) / c.pixelSize - 1e-4f)));
  c.origin = lo[0] * c.axisU + lo[1] * c.axisV;
  // A little room in depth so surfaces on the box's faces are not cut by rounding.
  const float pad = 1e-3f * (hi[2] - lo[2]) + 1e-4f;
  c.depthMin = lo[2] - pad;
  c.depthMax = hi[2] + pad;
  return c;
}

glm::vec3 ldiPoint(const LdiCamera& c, uint32_t column, uint32_t row, uint32_t depth) {
  const float t = c.depthMin + float(depth) * (c.depthMax - c.depthMin) / float(kLdiMaxDepth);
  return c.origin + (float(column) + 0.5f) * c.pixelSize * c.axisU +
         (float(row) + 0.5f) * c.pixelSize * c.axisV + t * c.direction;
}

}  // namespace terralod::veg
