#include "terralod/runtime/overview.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <string>

namespace terralod {
namespace {

struct Framing {
  bool allInside = true;
  double widthFilled = 0, heightFilled = 0;  ///< fraction of the image the corners span
};

// Projects the box's corners through the camera's own view (as the renderer would).
Framing frame(const Camera& camera, const Box& box) {
  const View v = makeView(camera).value();
  Framing out;
  double left = 1e300, right = -1e300, bottom = 1e300, top = -1e300;
  for (int k = 0; k < 8; ++k) {
    const glm::dvec3 p{(k & 1) ? box.max[0] : box.min[0], (k & 2) ? box.max[1] : box.min[1],
                       (k & 4) ? box.max[2] : box.min[2]};
    const glm::dvec3 q = p - camera.eye;
    const double z = glm::dot(q, v.forward);
    if (!(z > 0)) {
      out.allInside = false;
      continue;
    }
    const double x = glm::dot(q, v.right) / (z * v.tanHalfWidth);
    const double y = glm::dot(q, v.up) / (z * v.tanHalfHeight);
    if (std::abs(x) > 1 + 1e-9 || std::abs(y) > 1 + 1e-9) out.allInside = false;
    left = std::min(left, x);
    right = std::max(right, x);
    bottom = std::min(bottom, y);
    top = std::max(top, y);
  }
  out.widthFilled = (right - left) / 2;
  out.heightFilled = (top - bottom) / 2;
  return out;
}

Box box(double w, double h, double z0, double z1) {
  Box b;
  b.min = {0.0, 0.0, z0};
  b.max = {w, h, z1};
  return b;
}

TEST(Overview, FramesEveryCornerOfWideTallAndSquareRastersInWideAndTallImages) {
  // Rasters 4:1 wide, 1:4 tall (like the Alps tile at 46°N, or Kauai), square, and flat.
  const std::pair<const char*, Box> boxes[] = {
      {"wide", box(40000, 10000, 100, 2500)}, {"tall", box(10000, 40000, 100, 2500)},
      {"square", box(20000, 20000, 0, 4000)}, {"flat", box(20000, 10000, 50, 50)},
      {"needle", box(100, 100, 0, 3000)},     {"very tall", box(1000, 100000, 0, 100)}};
  const std::pair<int, int> images[] = {{1024, 768}, {768, 1024}, {400, 400}, {1600, 400}};
  for (const auto& [name, b] : boxes)
    for (const auto& [w, h] : images)
      for (double heading : {0.0, 45.0, 200.0})
        for (double pitch : {20.0, 40.0, 90.0}) {
          OverviewOptions o;
          o.width = w;
          o.height = h;
          o.headingDegrees = heading;
          o.pitchDegrees = pitch;
          const std::string what = std::string(name) + " in " + std::to_string(w) + "x" +
                                   std::to_string(h) + " heading " + std::to_string(heading) +
                                   " pitch " + std::to_string(pitch);
          const Camera c = overviewCamera(b, o);
          ASSERT_TRUE(makeView(c).ok()) << what;
          const Framing f = frame(c, b);
          EXPECT_TRUE(f.allInside) << what;
          // Tight in one direction (up to the 3 % margins), not lost in the middle.
          EXPECT_GE(std::max(f.widthFilled, f.heightFilled), 0.9) << what;
        }
}

TEST(Overview, DefaultLooksNorthAndDownAtTheCentre) {
  const Box b = box(10000, 40000, 100, 2500);
  const Camera c = overviewCamera(b, OverviewOptions{});
  const glm::dvec3 look = glm::normalize(c.target - c.eye);
  EXPECT_NEAR(look.x, 0.0, 1e-12);
  EXPECT_GT(look.y, 0.0);
  EXPECT_NEAR(std::asin(-look.z) * 180 / 3.14159265358979, 40.0, 1e-9);
  EXPECT_NEAR(c.eye.x, 5000.0, 1e-6);  // centred across the image
  EXPECT_LT(c.eye.y, 0.0);             // from the south of the data
  EXPECT_GT(c.eye.z, 2500.0);
}

// The overview this replaced stood 0.75 · the longer side south of the centre: the south edge
// of a tall raster fell below the image (the Alps at 1024x768: its southern sixth).
TEST(Overview, TheOldOverviewCroppedTallRasters) {
  const Box b = box(77000, 111000, 200, 4600);  // N46E008 in metres, about
  Camera old;
  const glm::dvec3 centre{38500, 55500, 2400};
  old.target = centre;
  old.eye = centre + glm::dvec3(0.0, -0.75 * 111000, 0.6 * 111000 + 4400);
  EXPECT_FALSE(frame(old, b).allInside);
  EXPECT_TRUE(frame(overviewCamera(b, OverviewOptions{}), b).allInside);
}

}  // namespace
}  // namespace terralod
