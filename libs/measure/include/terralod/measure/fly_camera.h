#pragma once
// The viewer's camera: mouse-look and WASD flight whose speed follows the height above the
// ground, or a walk that keeps the eye at head height over it. Pure state and arithmetic, so
// it is tested without a window.

#include <functional>
#include <glm/glm.hpp>

#include "terralod/runtime/view.h"

namespace terralod {

/// What the user is pressing this frame.
struct FlyInput {
  double forward = 0, right = 0, up = 0;  ///< each -1..1 (W/S, D/A, E/Q)
  double lookRight = 0, lookUp = 0;       ///< radians to turn this frame (from the mouse)
  bool fast = false;                      ///< shift: five times faster
};

class FlyCamera {
 public:
  /// Starts at `camera`'s eye, looking at its target.
  explicit FlyCamera(const Camera& camera);

  /// Moves for `seconds` of `input`. `ground(x, y)` gives the terrain height there.
  void update(const FlyInput& input, double seconds,
              const std::function<double(double, double)>& ground);

  /// The camera to render (the viewport and field of view are the caller's).
  Camera camera(int width, int height, double fovDegrees) const;

  bool walking = false;                       ///< keep the eye kWalkHeight above the ground
  static constexpr double kWalkHeight = 1.8;  ///< metres
  glm::dvec3 eye{0.0};
  double yaw = 0.0;    ///< radians, 0 = north, clockwise
  double pitch = 0.0;  ///< radians, positive up

 private:
  glm::dvec3 forwardVector() const;
};

}  // namespace terralod
