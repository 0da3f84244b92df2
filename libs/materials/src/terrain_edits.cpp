#include "terralod/materials/terrain_edits.h"

#include <algorithm>
#include <cmath>

namespace terralod {
namespace {

// Calls f(x, y, w) for every grid point of the window with a weight w > 0.
template <typename F>
void forEachTouched(const TerrainEdit& e, double sx, double sy, const GridWindow& w, F&& f) {
  for (int32_t y = w.y0; y <= w.y1; ++y)
    for (int32_t x = w.x0; x <= w.x1; ++x) {
      const double weight =
          brushWeight(std::hypot(x * sx - e.centerX, y * sy - e.centerY), e.radius);
      if (weight > 0.0) f(x, y, weight);
    }
}

void smooth(const TerrainEdit& e, double sx, double sy, const GridWindow& w, Heightfield& h) {
  // The heights before the stroke, one point around the window.
  const int32_t bx0 = w.x0 - 1, by0 = w.y0 - 1, bw = w.x1 - w.x0 + 3;
  std::vector<float> before(size_t(bw) * size_t(w.y1 - w.y0 + 3));
  for (int32_t y = w.y0 - 1; y <= w.y1 + 1; ++y)
    for (int32_t x = w.x0 - 1; x <= w.x1 + 1; ++x)
      before[size_t(y - by0) * size_t(bw) + size_t(x - bx0)] = h.at(x, y);
  forEachTouched(e, sx, sy, w, [&](int32_t x, int32_t y, double weight) {
    double sum = 0.0;
    for (int32_t dy = -1; dy <= 1; ++dy)
      for (int32_t dx = -1; dx <= 1; ++dx)
        sum += before[size_t(y + dy - by0) * size_t(bw) + size_t(x + dx - bx0)];
    const double here = h(x, y);
    h(x, y) = float(here + e.amount * weight * (sum / 9.0 - here));
  });
}

}  // namespace

bool windowMeets(const GridWindow& w, int32_t x0, int32_t y0, int32_t width, int32_t height,
                 int32_t margin) {
  return !w.empty() && w.x0 <= x0 + width - 1 + margin && w.x1 >= x0 - margin &&
         w.y0 <= y0 + height - 1 + margin && w.y1 >= y0 - margin;
}

GridWindow editWindow(const TerrainEdit& e, double sx, double sy, int32_t columns, int32_t rows) {
  auto clampTo = [](double v, int32_t hi) {
    return int32_t(std::clamp(v, -1.0, double(hi) + 1.0));
  };
  GridWindow w;
  w.x0 = std::max(0, clampTo(std::ceil((e.centerX - e.radius) / sx), columns));
  w.x1 = std::min(columns - 1, clampTo(std::floor((e.centerX + e.radius) / sx), columns));
  w.y0 = std::max(0, clampTo(std::ceil((e.centerY - e.radius) / sy), rows));
  w.y1 = std::min(rows - 1, clampTo(std::floor((e.centerY + e.radius) / sy), rows));
  return w;
}

uint64_t touchedPoints(const TerrainEdit& e, double sx, double sy, int32_t columns, int32_t rows) {
  uint64_t count = 0;
  forEachTouched(e, sx, sy, editWindow(e, sx, sy, columns, rows),
                 [&](int32_t, int32_t, double) { ++count; });
  return count;
}

double brushWeight(double distance, double radius) {
  if (!(distance < radius)) return 0.0;
  const double q = 1.0 - (distance / radius) * (distance / radius);
  return q * q;
}

void applyHeightEdits(const std::vector<TerrainEdit>& edits, double sx, double sy,
                      Heightfield& heights) {
  for (const TerrainEdit& e : edits) {
    const GridWindow w = editWindow(e, sx, sy, heights.columns(), heights.rows());
    if (w.empty() || e.brush == Brush::kPaint) continue;
    if (e.brush == Brush::kSmooth) {
      smooth(e, sx, sy, w, heights);
      continue;
    }
    const double sign = e.brush == Brush::kRaise ? 1.0 : -1.0;
    forEachTouched(e, sx, sy, w, [&](int32_t x, int32_t y, double weight) {
      heights(x, y) = float(double(heights(x, y)) + sign * e.amount * weight);
    });
  }
}

Status checkPaintMaterials(const std::vector<TerrainEdit>& edits, const MaterialMap& materials,
                           const std::string& subject) {
  for (size_t i = 0; i < edits.size(); ++i) {
    const TerrainEdit& e = edits[i];
    if (e.brush != Brush::kPaint ||
        std::any_of(materials.materials.begin(), materials.materials.end(),
                    [&](const Material& m) { return m.id == e.material; }))
      continue;
    std::string known;
    for (const Material& m : materials.materials)
      known += (known.empty() ? "" : ", ") + std::to_string(m.id) + " " + m.name;
    return makeError(subject, "edit " + std::to_string(i) + " paints material " +
                                  std::to_string(e.material) +
                                  ", which the tileset does not have (" + known + ")");
  }
  return {};
}

Status applyPaintEdits(const std::vector<TerrainEdit>& edits, double sx, double sy,
                       MaterialMap& materials, const std::string& subject) {
  if (Status s = checkPaintMaterials(edits, materials, subject); !s) return s;
  for (const TerrainEdit& e : edits) {
    if (e.brush != Brush::kPaint) continue;
    const auto found = std::find_if(materials.materials.begin(), materials.materials.end(),
                                    [&](const Material& m) { return m.id == e.material; });
    const uint8_t index = uint8_t(found - materials.materials.begin());
    const GridWindow w = editWindow(e, sx, sy, materials.columns, materials.rows);
    if (w.empty()) continue;
    forEachTouched(e, sx, sy, w, [&](int32_t x, int32_t y, double) {
      materials.classes[size_t(y) * size_t(materials.columns) + size_t(x)] = index;
    });
  }
  return {};
}

}  // namespace terralod
