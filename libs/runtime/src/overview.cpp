#include "terralod/runtime/overview.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace terralod {

Camera overviewCamera(const Box& box, const OverviewOptions& o) {
  constexpr double kRadians = std::numbers::pi / 180.0;
  const double heading = o.headingDegrees * kRadians;
  const double pitch = std::clamp(o.pitchDegrees, 1e-3, 90.0) * kRadians;
  // The camera's frame, exactly as makeView derives it (its eye plays no part in it).
  Camera c;
  c.hfovDegrees = std::clamp(o.hfovDegrees, 1e-3, 179.0);
  c.width = std::max(o.width, 1);
  c.height = std::max(o.height, 1);
  c.eye = glm::dvec3(0.0);
  c.target = glm::dvec3(std::sin(heading) * std::cos(pitch), std::cos(heading) * std::cos(pitch),
                        -std::sin(pitch));
  const View frame = makeView(c).value();
  const glm::dvec3 f = frame.forward, r = frame.right, u = frame.up;
  const double margin = std::clamp(o.margin, 0.0, 0.45);
  const double tw = frame.tanHalfWidth * (1.0 - 2.0 * margin);
  const double th = frame.tanHalfHeight * (1.0 - 2.0 * margin);

  // In the camera's frame around the box's centre, a corner (x, y, z) is in view from an eye at
  // (ex, ey, ez) when |x − ex| <= tw (z − ez) and |y − ey| <= th (z − ez): linear in the eye.
  // Across the image that asks ex − tw·ez >= max(x − tw·z) = a and ex + tw·ez <= min(x + tw·z)
  // = b, which leaves ez <= (b − a) / (2 tw) with ex = (a + b) / 2; likewise up the image. The
  // nearer of the two distances frames the box tightly in one direction, centred in the other.
  const glm::dvec3 centre{0.5 * (box.min[0] + box.max[0]), 0.5 * (box.min[1] + box.max[1]),
                          0.5 * (box.min[2] + box.max[2])};
  constexpr double kHuge = std::numeric_limits<double>::infinity();
  double a = -kHuge, b = kHuge, cc = -kHuge, d = kHuge, nearest = kHuge;
  for (int k = 0; k < 8; ++k) {
    const glm::dvec3 p =
        glm::dvec3{(k & 1) ? box.max[0] : box.min[0], (k & 2) ? box.max[1] : box.min[1],
                   (k & 4) ? box.max[2] : box.min[2]} -
        centre;
    const double x = glm::dot(p, r), y = glm::dot(p, u), z = glm::dot(p, f);
    a = std::max(a, x - tw * z);
    b = std::min(b, x + tw * z);
    cc = std::max(cc, y - th * z);
    d = std::min(d, y + th * z);
    nearest = std::min(nearest, z);
  }
  const glm::dvec3 size{box.max[0] - box.min[0], box.max[1] - box.min[1], box.max[2] - box.min[2]};
  // Never on a corner, even for a box without width or height.
  const double clearance = 1e-3 * std::max(glm::length(size), 1.0);
  const double ez = std::min({(b - a) / (2.0 * tw), (d - cc) / (2.0 * th), nearest - clearance});
  c.eye = centre + r * (0.5 * (a + b)) + u * (0.5 * (cc + d)) + f * ez;
  c.target = c.eye + f * std::max(-ez, clearance);
  return c;
}

}  // namespace terralod
