#pragma once
// Deterministic, deliberately nasty heightfields for the builder's tests: smooth hills, fractal
// roughness, a cliff, a flat plateau, isolated spikes and pits.

#include <gdal_priv.h>
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>

#include "terralod/raster/heightfield.h"

namespace terralod::test {

inline Heightfield makeTestTerrain(int32_t columns, int32_t rows, uint32_t seed,
                                   double roughness = 1.0) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  Heightfield h(columns, rows);
  struct Wave {
    double fx, fy, phase, amplitude;
  };
  std::vector<Wave> waves;
  for (int i = 0; i < 12; ++i) {
    const double scale = std::pow(2.0, -i * 0.5);
    waves.push_back({unit(rng) * 0.3 / scale, unit(rng) * 0.3 / scale, unit(rng) * 6.28,
                     40.0 * scale * (0.5 + unit(rng))});
  }
  for (int32_t y = 0; y < rows; ++y)
    for (int32_t x = 0; x < columns; ++x) {
      double z = 100.0;
      for (const Wave& w : waves) z += w.amplitude * std::sin(w.fx * x + w.fy * y + w.phase);
      z += roughness * 3.0 * (unit(rng) - 0.5);               // white noise
      if (x > columns / 2 && x < columns / 2 + 3) z += 30.0;  // a narrow ridge
      if (y > rows * 2 / 3) z = std::max(z, 180.0) - 60.0;    // a cliff
      if (x < columns / 4 && y < rows / 4) z = 55.0;          // a flat plateau
      h(x, y) = static_cast<float>(z);
    }
  for (int i = 0; i < 6; ++i) {  // spikes and pits
    const int32_t x = int32_t(unit(rng) * (columns - 1)), y = int32_t(unit(rng) * (rows - 1));
    h(x, y) += static_cast<float>((i % 2 ? -1 : 1) * 80.0 * (0.5 + unit(rng)));
  }
  return h;
}

/// Writes a float32 GeoTIFF in a projected CRS with the given spacing (north-up: grid row 0 is
/// the last raster row). NaN samples become nodata.
inline void writeGeoTiff(const Heightfield& h, const std::string& path, double spacing = 1.0) {
  GDALAllRegister();
  GDALDriver* driver = GetGDALDriverManager()->GetDriverByName("GTiff");
  GDALDataset* ds = driver->Create(path.c_str(), h.columns(), h.rows(), 1, GDT_Float32, nullptr);
  double gt[6] = {500000.0, spacing, 0.0, 4000000.0, 0.0, -spacing};
  ds->SetGeoTransform(gt);
  OGRSpatialReference srs;
  srs.importFromEPSG(32610);
  ds->SetSpatialRef(&srs);
  GDALRasterBand* band = ds->GetRasterBand(1);
  band->SetNoDataValue(-9999.0);
  std::vector<float> row(h.columns());
  for (int32_t r = 0; r < h.rows(); ++r) {
    const float* src = h.row(h.rows() - 1 - r);
    for (int32_t x = 0; x < h.columns(); ++x) row[x] = std::isnan(src[x]) ? -9999.0f : src[x];
    EXPECT_EQ(band->RasterIO(GF_Write, 0, r, h.columns(), 1, row.data(), h.columns(), 1,
                             GDT_Float32, 0, 0),
              CE_None);
  }
  GDALClose(ds);
}

}  // namespace terralod::test
