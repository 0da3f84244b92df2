#include "terralod/runtime/view.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>

namespace terralod {
namespace {

// The box corner furthest along `direction`.
glm::dvec3 furthestCorner(const Box& b, const glm::dvec3& direction) {
  return {direction.x >= 0 ? b.max[0] : b.min[0], direction.y >= 0 ? b.max[1] : b.min[1],
          direction.z >= 0 ? b.max[2] : b.min[2]};
}

bool insidePlane(const glm::dvec4& plane, const glm::dvec3& p) {
  return glm::dot(glm::dvec3(plane), p) + plane.w >= 0.0;
}

bool finite(const glm::dvec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

glm::dvec4 planeThrough(const glm::dvec3& point, const glm::dvec3& inwardNormal) {
  const glm::dvec3 n = glm::normalize(inwardNormal);
  return {n, -glm::dot(n, point)};
}

}  // namespace

Result<View> makeView(const Camera& c) {
  if (!finite(c.eye) || !finite(c.target)) return Error{"camera coordinates must be finite"};
  if (!(c.width > 0 && c.height > 0))
    return Error{"viewport " + std::to_string(c.width) + "x" + std::to_string(c.height) +
                 " must have a positive width and height"};
  if (!(c.hfovDegrees > 0.0 && c.hfovDegrees < 180.0))
    return Error{"field of view must be between 0 and 180 degrees"};
  const glm::dvec3 towards = c.target - c.eye;
  const double length = glm::length(towards);
  if (!(length > 1e-9 * std::max(1.0, glm::length(c.eye))))
    return Error{"eye and target must be different points"};

  View v;
  v.camera = c;
  v.forward = towards / length;
  // Straight up or down the world's z gives no horizon: use north (or south) as image up.
  glm::dvec3 worldUp{0.0, 0.0, 1.0};
  if (std::fabs(v.forward.z) > 0.999999) worldUp = {0.0, v.forward.z < 0 ? 1.0 : -1.0, 0.0};
  v.right = glm::normalize(glm::cross(v.forward, worldUp));
  v.up = glm::cross(v.right, v.forward);
  v.tanHalfWidth = std::tan(c.hfovDegrees * std::numbers::pi / 360.0);
  v.tanHalfHeight = v.tanHalfWidth * double(c.height) / double(c.width);
  v.pixelsPerRadian = double(c.width) / (2.0 * v.tanHalfWidth);

  const glm::dvec3& e = c.eye;
  const glm::dvec3 f = v.forward, r = v.right, u = v.up;
  v.planes[0] = planeThrough(e, r + f * v.tanHalfWidth);    // left
  v.planes[1] = planeThrough(e, -r + f * v.tanHalfWidth);   // right
  v.planes[2] = planeThrough(e, u + f * v.tanHalfHeight);   // bottom
  v.planes[3] = planeThrough(e, -u + f * v.tanHalfHeight);  // top
  v.planes[4] = planeThrough(e, f);                         // near, through the eye
  return v;
}

double distanceToBox(const glm::dvec3& p, const Box& b) {
  double sum = 0.0;
  for (int k = 0; k < 3; ++k) {
    const double below = b.min[k] - p[k], above = p[k] - b.max[k];
    const double d = std::max({below, above, 0.0});
    sum += d * d;
  }
  return std::sqrt(sum);
}

bool boxInFrustum(const View& view, const Box& b) {
  // Per plane, the corner furthest along its normal decides.
  return std::all_of(view.planes.begin(), view.planes.end(), [&](const glm::dvec4& plane) {
    return insidePlane(plane, furthestCorner(b, glm::dvec3(plane)));
  });
}

bool boxWithinFrustum(const View& view, const Box& b) {
  // Per plane, the corner nearest along its normal decides.
  return std::all_of(view.planes.begin(), view.planes.end(), [&](const glm::dvec4& plane) {
    return insidePlane(plane, furthestCorner(b, -glm::dvec3(plane)));
  });
}

double screenSpaceError(const View& view, double error, double distance) {
  if (distance <= 0.0) return std::numeric_limits<double>::infinity();
  return error * view.pixelsPerRadian / distance;
}

}  // namespace terralod
