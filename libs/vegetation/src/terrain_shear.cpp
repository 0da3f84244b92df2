#include "terralod/vegetation/terrain_shear.h"

namespace terralod::veg {

glm::mat4 halfShear(const TileOnTerrain& t, TileHalf half) {
  const float s = t.size, sw = t.heights[0], se = t.heights[1], ne = t.heights[2],
              nw = t.heights[3];
  // h(x, y) = a·x + b·y + c through SW (0,0), NE (s,s) and SE (s,0) or NW (0,s).
  const float c = sw;
  float a, b;
  if (half == TileHalf::kSouthEast) {
    a = (se - sw) / s;
    b = (ne - se) / s;
  } else {
    a = (ne - nw) / s;
    b = (nw - sw) / s;
  }
  glm::mat4 m(1.0f);  // column-major: m[column][row]
  m[0][2] = a;
  m[1][2] = b;
  m[3] = glm::vec4(t.origin.x, t.origin.y, c, 1.0f);
  return m;
}

TileHalf farHalf(const TileOnTerrain& t, const glm::vec3& eye) {
  return halfOf(eye.x - t.origin.x, eye.y - t.origin.y) == TileHalf::kSouthEast
             ? TileHalf::kNorthWest
             : TileHalf::kSouthEast;
}

}  // namespace terralod::veg
