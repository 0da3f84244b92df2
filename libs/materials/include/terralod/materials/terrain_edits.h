#pragma once
// Applying brush strokes (terralod/core/terrain_edit.h) to a DEM's heights and materials: what
// `terralod edit` does before it rebuilds, and what `verify` does to the source of an edited
// tileset before it checks it. Pure and deterministic, so both get the same floats.
//
// A stroke touches the grid points strictly within `radius` metres of its centre (grid point
// (i, j) lies at (i spacingX, j spacingY)), with the weight w = (1 - (d/r)^2)^2: 1 at the
// centre, falling smoothly to 0 at the rim.
//   raise / lower: h += / -= amount w;
//   smooth: h += amount w (m - h), m the mean of the 3 x 3 points around (edge points repeat),
//           of the heights before the stroke;
//   paint: the point's material becomes the one with id `material`.
// Height strokes do not read materials and paint does not read heights, so the two lists can
// be applied apart; each in stroke order.

#include <cstdint>
#include <string>
#include <vector>

#include "terralod/core/result.h"
#include "terralod/core/terrain_edit.h"
#include "terralod/materials/material.h"
#include "terralod/raster/heightfield.h"

namespace terralod {

/// Grid points [x0, x1] x [y0, y1] (inclusive); empty when x0 > x1 or y0 > y1.
struct GridWindow {
  int32_t x0 = 0, y0 = 0, x1 = -1, y1 = -1;
  bool empty() const { return x0 > x1 || y0 > y1; }
};

/// Whether `w` meets the grid points [x0, x0 + width) x [y0, y0 + height) grown by `margin`.
bool windowMeets(const GridWindow& w, int32_t x0, int32_t y0, int32_t width, int32_t height,
                 int32_t margin);

/// The grid points within a stroke's radius lie inside this window of a columns x rows grid.
GridWindow editWindow(const TerrainEdit& edit, double spacingX, double spacingY, int32_t columns,
                      int32_t rows);

/// How many grid points of a columns x rows grid the stroke touches (weight > 0).
uint64_t touchedPoints(const TerrainEdit& edit, double spacingX, double spacingY, int32_t columns,
                       int32_t rows);

/// (1 - (d/r)^2)^2 for d < r, else 0.
double brushWeight(double distance, double radius);

void applyHeightEdits(const std::vector<TerrainEdit>& edits, double spacingX, double spacingY,
                      Heightfield& heights);

/// Fails (naming `subject`) when a paint stroke names a material id `materials` does not have.
Status checkPaintMaterials(const std::vector<TerrainEdit>& edits, const MaterialMap& materials,
                           const std::string& subject);

/// checkPaintMaterials, then the paint strokes (nothing is painted when it fails).
Status applyPaintEdits(const std::vector<TerrainEdit>& edits, double spacingX, double spacingY,
                       MaterialMap& materials, const std::string& subject);

}  // namespace terralod
