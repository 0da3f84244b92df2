#include "terralod/vegetation/placement_check.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <unordered_map>

#include "terralod/vegetation/tile_placement.h"

namespace terralod::veg {

std::vector<TilingPoint> tilingPoints(const std::vector<PrototileContent>& tiles, float tileSize,
                                      const WangTiling& tiling) {
  std::vector<TilingPoint> points;
  for (uint32_t ty = 0; ty < tiling.height(); ++ty)
    for (uint32_t tx = 0; tx < tiling.width(); ++tx)
      for (const PlacedObject& o : tiles[tiling.at(tx, ty)].objects)
        if (centredIn(o, tileSize))
          points.push_back({double(tx) * tileSize + o.x, double(ty) * tileSize + o.y, &o, tx, ty});
  return points;
}

namespace {

// Tiling points binned in square cells at least as wide as any interaction distance.
class PointGrid {
 public:
  PointGrid(const std::vector<TilingPoint>& points, double cell) : mCell(cell) {
    for (size_t i = 0; i < points.size(); ++i)
      mCells[key(cellOf(points[i].x), cellOf(points[i].y))].push_back(i);
  }
  template <typename Fn>
  void forNear(double x, double y, Fn&& fn) const {
    const int64_t cx = cellOf(x), cy = cellOf(y);
    for (int64_t dy = -1; dy <= 1; ++dy)
      for (int64_t dx = -1; dx <= 1; ++dx) {
        auto it = mCells.find(key(cx + dx, cy + dy));
        if (it != mCells.end())
          for (size_t i : it->second) fn(i);
      }
  }

 private:
  int64_t cellOf(double v) const { return int64_t(std::floor(v / mCell)); }
  static uint64_t key(int64_t x, int64_t y) { return uint64_t(x) << 32 ^ uint64_t(uint32_t(y)); }
  double mCell;
  std::unordered_map<uint64_t, std::vector<size_t>> mCells;
};

int edgesWithin(const PlacedObject& o, float size, double distance) {
  return (o.x < distance) + (size - o.x < distance) + (o.y < distance) + (size - o.y < distance);
}

}  // namespace

PlacementReport checkPlacement(const std::vector<PrototileContent>& tiles, float tileSize,
                               const WangTiling& tiling, double band) {
  const std::vector<TilingPoint> points = tilingPoints(tiles, tileSize, tiling);
  PlacementReport r;
  r.objects = points.size();
  double maxPacking = 0;
  for (const TilingPoint& p : points)
    maxPacking = std::max<double>(maxPacking, p.object->packingRadius);
  r.band = band > 0 ? band : 2 * maxPacking;
  r.minTightRatio = r.minPackingRatio = std::numeric_limits<double>::infinity();
  if (points.empty()) return r;
  const PointGrid grid(points, std::max(2 * maxPacking, 1e-6));
  for (size_t i = 0; i < points.size(); ++i) {
    const TilingPoint& a = points[i];
    r.tightAcrossCorners += edgesWithin(*a.object, tileSize, a.object->tightRadius) > 1;
    grid.forNear(a.x, a.y, [&](size_t j) {
      if (j <= i) return;
      const TilingPoint& b = points[j];
      const double d = std::hypot(a.x - b.x, a.y - b.y);
      const double tight = a.object->tightRadius + b.object->tightRadius;
      const double packing = a.object->packingRadius + b.object->packingRadius;
      const bool diagonal = a.tileX != b.tileX && a.tileY != b.tileY;
      if (d < packing * 1.5) r.minTightRatio = std::min(r.minTightRatio, d / tight);
      if (d < tight) ++r.tightOverlaps;
      if (!diagonal && d < packing * 1.5)
        r.minPackingRatio = std::min(r.minPackingRatio, d / packing);
      if (d < packing) ++(diagonal ? r.packingAcrossCorners : r.packingOverlaps);
    });
  }
  const double inner = std::max(0.0, tileSize - 2 * r.band);
  const double tilesCount = double(tiling.width()) * tiling.height();
  uint64_t counts[3] = {0, 0, 0};
  for (const TilingPoint& p : points)
    ++counts[std::min(2, edgesWithin(*p.object, tileSize, r.band))];
  const double areas[3] = {inner * inner, 4 * r.band * inner, 4 * r.band * r.band};
  double* densities[3] = {&r.interiorDensity, &r.edgeDensity, &r.cornerDensity};
  for (int k = 0; k < 3; ++k)
    *densities[k] = areas[k] > 0 ? counts[k] / (areas[k] * tilesCount) : 0;
  return r;
}

std::vector<double> foldedDensity(const std::vector<TilingPoint>& points, float tileSize,
                                  int bins) {
  std::vector<double> d(size_t(bins) * bins, 0.0);
  for (const TilingPoint& p : points) {
    const int bx = std::clamp(int(p.object->x / tileSize * bins), 0, bins - 1);
    const int by = std::clamp(int(p.object->y / tileSize * bins), 0, bins - 1);
    d[size_t(by) * bins + bx] += 1;
  }
  const double mean = points.empty() ? 1 : double(points.size()) / d.size();
  for (double& v : d) v /= mean;
  return d;
}

}  // namespace terralod::veg
