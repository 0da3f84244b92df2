#include "terralod/measure/fly_camera.h"

#include <algorithm>
#include <cmath>

namespace terralod {
namespace {

constexpr double kMaxPitch = 1.55;  // just short of straight up or down
constexpr double kMinSpeed = 2.0;   // metres per second, at the ground
constexpr double kWalkSpeed = 1.5;

}  // namespace

FlyCamera::FlyCamera(const Camera& c) : eye(c.eye) {
  const glm::dvec3 d = glm::normalize(c.target - c.eye);
  yaw = std::atan2(d.x, d.y);
  pitch = std::asin(std::clamp(d.z, -1.0, 1.0));
}

glm::dvec3 FlyCamera::forwardVector() const {
  return {std::sin(yaw) * std::cos(pitch), std::cos(yaw) * std::cos(pitch), std::sin(pitch)};
}

void FlyCamera::update(const FlyInput& in, double seconds,
                       const std::function<double(double, double)>& ground) {
  yaw += in.lookRight;
  pitch = std::clamp(pitch + in.lookUp, -kMaxPitch, kMaxPitch);
  const double floor = ground(eye.x, eye.y);
  // Flying, cover about the height above the ground each second: slow near it, fast high up.
  double speed = walking ? kWalkSpeed : std::max(kMinSpeed, eye.z - floor);
  if (in.fast) speed *= 5.0;
  const glm::dvec3 right{std::cos(yaw), -std::sin(yaw), 0.0};
  glm::dvec3 forward = forwardVector();
  if (walking) forward = glm::normalize(glm::dvec3(forward.x, forward.y, 0.0));
  eye += (forward * in.forward + right * in.right + glm::dvec3(0, 0, walking ? 0.0 : in.up)) *
         speed * seconds;
  const double below = ground(eye.x, eye.y);
  if (walking)
    eye.z = below + kWalkHeight;
  else
    eye.z = std::max(eye.z, below + 0.5);  // never into the ground
}

Camera FlyCamera::camera(int width, int height, double fovDegrees) const {
  Camera c;
  c.eye = eye;
  c.target = eye + forwardVector();
  c.width = width;
  c.height = height;
  c.hfovDegrees = fovDegrees;
  return c;
}

}  // namespace terralod
