#include "terralod/vegetation/material_mask.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace terralod::veg {

bool MaterialMask::allowsAt(double x, double y) const {
  if (columns <= 0 || rows <= 0) return false;
  const auto nearest = [](double v, double cell, int32_t count) {
    const double i = std::floor(v / cell + 0.5);
    return int32_t(std::clamp(i, 0.0, double(count - 1)));
  };
  return allowed[size_t(nearest(y, cellY, rows)) * size_t(columns) +
                 size_t(nearest(x, cellX, columns))] != 0;
}

Result<MaterialMask> MaterialMask::from(const MaterialMap& map, double spacingX, double spacingY,
                                        const std::vector<std::string>& names,
                                        const std::string& source) {
  std::array<bool, 256> wanted{};
  for (const std::string& name : names) {
    const auto it = std::find_if(map.materials.begin(), map.materials.end(),
                                 [&](const Material& m) { return m.name == name; });
    if (it == map.materials.end()) {
      std::string known;
      for (const Material& m : map.materials) known += (known.empty() ? "" : ", ") + m.name;
      return makeError("--vegetation-where",
                       "material '" + name + "' is not one of: " + known + " (in " + source + ")");
    }
    wanted[size_t(it - map.materials.begin())] = true;
  }
  const int32_t step = std::max<int32_t>(
      1, (std::max(map.columns, map.rows) + kMaxMaterialMaskSide - 1) / kMaxMaterialMaskSide);
  MaterialMask mask;
  mask.columns = (map.columns + step - 1) / step;
  mask.rows = (map.rows + step - 1) / step;
  mask.cellX = spacingX * step;
  mask.cellY = spacingY * step;
  mask.allowed.resize(size_t(mask.columns) * size_t(mask.rows));
  for (int32_t r = 0; r < mask.rows; ++r)
    for (int32_t c = 0; c < mask.columns; ++c)
      mask.allowed[size_t(r) * size_t(mask.columns) + size_t(c)] =
          wanted[map.at(c * step, r * step)] ? 1 : 0;
  return mask;
}

}  // namespace terralod::veg
