#include "terralod/materials/dem_classification.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

namespace terralod {
namespace {

constexpr int32_t kBandRows = 256;
constexpr int kHalo = DemClassificationRules::kFlatRadius;

double tanSquared(double degrees) {
  const double t = std::tan(degrees * std::numbers::pi / 180.0);
  return t * t;
}

// The exact height range over all non-void samples, read band by band.
Result<std::array<double, 2>> heightRange(const DemReader& dem, Progress& progress) {
  const DemInfo& info = dem.info();
  std::vector<float> band(size_t(info.columns) * kBandRows);
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (int32_t y0 = 0; y0 < info.rows; y0 += kBandRows) {
    const int32_t h = std::min(kBandRows, info.rows - y0);
    if (Status read = dem.readWindow(0, y0, info.columns, h, band.data()); !read)
      return read.error();
    for (size_t i = 0; i < size_t(info.columns) * size_t(h); ++i) {
      const float v = band[i];
      if (std::isnan(v)) continue;
      lo = std::min(lo, double(v));
      hi = std::max(hi, double(v));
    }
    progress.advance(uint64_t(h));
  }
  return std::array<double, 2>{lo, hi};
}

}  // namespace

std::vector<Material> demClassificationMaterials() {
  return {
      {kWater, "water", {58, 96, 128}}, {kGrass, "grass", {96, 124, 60}},
      {kSoil, "soil", {128, 104, 76}},  {kRock, "rock", {112, 108, 104}},
      {kSnow, "snow", {236, 240, 244}},
  };
}

Result<MaterialMap> classifyDem(const DemReader& dem, Progress* progress) {
  NullProgress silent;
  Progress& report = progress ? *progress : silent;
  const DemInfo& info = dem.info();
  const int32_t columns = info.columns, rows = info.rows;
  MaterialMap map;
  map.columns = columns;
  map.rows = rows;
  map.materials = demClassificationMaterials();
  map.classes.assign(size_t(columns) * size_t(rows), kWater);

  report.begin("classify DEM", 2 * uint64_t(rows));
  auto range = heightRange(dem, report);
  if (!range) {
    report.end();
    return range.error();
  }
  const double lo = (*range)[0], hi = (*range)[1];
  const double span = hi > lo ? hi - lo : 0.0;
  // Relative height thresholds as heights (a flat or all-void DEM: nothing is above them).
  const double inf = std::numeric_limits<double>::infinity();
  const double waterBelow = span > 0 ? lo + DemClassificationRules::kWaterBelow * span : -inf;
  const double snowLine = span > 0 ? lo + DemClassificationRules::kSnowLine * span : inf;
  const double highGround = span > 0 ? lo + DemClassificationRules::kHighGround * span : inf;
  const double rockT2 = tanSquared(DemClassificationRules::kRockSlopeDegrees);
  const double soilT2 = tanSquared(DemClassificationRules::kSoilSlopeDegrees);
  const double waterT2 = tanSquared(DemClassificationRules::kWaterSlopeDegrees);

  // Each band is read with a halo of kHalo samples on every side (readWindow replicates the
  // edge samples beyond the raster, which is the clamping rule 4 wants).
  const int32_t stride = columns + 2 * kHalo;
  std::vector<float> band(size_t(stride) * (kBandRows + 2 * kHalo));
  for (int32_t y0 = 0; y0 < rows; y0 += kBandRows) {
    const int32_t h = std::min(kBandRows, rows - y0);
    if (Status read = dem.readWindow(-kHalo, y0 - kHalo, stride, h + 2 * kHalo, band.data());
        !read) {
      report.end();
      return read.error();
    }
    auto sample = [&](int32_t x, int32_t y) {  // grid coordinates
      return band[size_t(y - y0 + kHalo) * size_t(stride) + size_t(x + kHalo)];
    };
    for (int32_t y = y0; y < y0 + h; ++y) {
      uint8_t* out = map.classes.data() + size_t(y) * size_t(columns);
      for (int32_t x = 0; x < columns; ++x) {
        const float c = sample(x, y);
        if (std::isnan(c)) {
          out[x] = kWater;
          continue;
        }
        // Central differences; one-sided on the DEM's edges and towards a void neighbour.
        auto gradient = [&](int32_t lx, int32_t ly, int32_t rx, int32_t ry, bool lIn, bool rIn,
                            double spacing) {
          float l = lIn ? sample(lx, ly) : c, r = rIn ? sample(rx, ry) : c;
          int steps = 2;
          if (!lIn || std::isnan(l)) l = c, --steps;
          if (!rIn || std::isnan(r)) r = c, --steps;
          return steps == 0 ? 0.0 : double(r - l) / (steps * spacing);
        };
        const double gx = gradient(x - 1, y, x + 1, y, x > 0, x + 1 < columns, info.spacingX);
        const double gy = gradient(x, y - 1, x, y + 1, y > 0, y + 1 < rows, info.spacingY);
        const double slope2 = gx * gx + gy * gy;
        uint8_t m;
        if (slope2 >= rockT2) {
          m = kRock;
        } else if (slope2 < waterT2 && c < waterBelow) {
          m = kWater;
        } else if (slope2 == 0.0 && [&] {
                     for (int32_t dy = -kHalo; dy <= kHalo; ++dy)
                       for (int32_t dx = -kHalo; dx <= kHalo; ++dx)
                         if (!(sample(x + dx, y + dy) == c)) return false;
                     return true;
                   }()) {
          m = kWater;
        } else if (c >= snowLine) {
          m = kSnow;
        } else if (slope2 >= soilT2 || c >= highGround) {
          m = kSoil;
        } else {
          m = kGrass;
        }
        out[x] = m;
      }
    }
    report.advance(uint64_t(h));
  }
  report.end();
  return map;
}

}  // namespace terralod
