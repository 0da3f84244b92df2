#pragma once
// A camera and what selection and culling derive from it. World frame: x east, y north, z up,
// metres (see the README's "World coordinates"). Pure values: no GL.

#include <array>
#include <glm/glm.hpp>

#include "terralod/core/result.h"
#include "terralod/runtime/chunk_tree.h"

namespace terralod {

struct Camera {
  glm::dvec3 eye{0.0};
  glm::dvec3 target{0.0, 1.0, 0.0};
  double hfovDegrees = 60.0;  ///< horizontal field of view
  int width = 1024, height = 768;
};

/// The camera's frame and frustum. The frustum has four side planes and a near plane through
/// the eye; there is no far plane (terrain ends where the data ends).
struct View {
  Camera camera;
  glm::dvec3 forward{0.0}, right{0.0}, up{0.0};  ///< orthonormal; up has a positive z part
  /// Ulrich's K: pixels per unit of (error / distance), width / (2 tan(hfov / 2)).
  double pixelsPerRadian = 0.0;
  double tanHalfWidth = 0.0, tanHalfHeight = 0.0;
  /// Inward-facing planes (n, d): a point p is inside when dot(n, p) + d >= 0.
  std::array<glm::dvec4, 5> planes{};
};

/// Validates the camera (finite coordinates, eye != target, a positive viewport, a field of
/// view in (0, 180) degrees) and derives its view. Looking straight up or down is allowed: the
/// image's up is then north (looking down) or south (looking up).
Result<View> makeView(const Camera& camera);

/// Euclidean distance from `p` to the box (0 inside it).
double distanceToBox(const glm::dvec3& p, const Box& box);

/// Conservative: false only when the box lies wholly outside one frustum plane.
bool boxInFrustum(const View& view, const Box& box);

/// True when the box lies wholly inside every frustum plane: then so does every point in it,
/// as computed in doubles (each plane's dot product only grows towards its furthest corner).
bool boxWithinFrustum(const View& view, const Box& box);

/// The surface error in pixels that a geometric error `error` at `distance` metres makes on
/// screen (Ulrich's eq. 2, ρ = δ K / D); infinite at distance 0.
double screenSpaceError(const View& view, double error, double distance);

}  // namespace terralod
