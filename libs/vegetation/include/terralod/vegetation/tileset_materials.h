#pragma once
// The materials under a tileset, for `--vegetation-where material=...` (material_mask.h), on
// the tileset's source grid (grid point (x, y) at x · spacingX, y · spacingY metres):
// - from a categorical raster (`--vegetation-materials`, as `build --materials` takes),
//   resampled onto the source grid through the georeferencing the tileset's metadata records
//   ("source": "geotransform" and "crs_wkt"; material_raster.h says how);
// - else a VIPM tileset's own: each grid point under a leaf's (or, where there is none, a
//   root's) full-detail triangles takes the material of the triangle's nearest corner; read
//   once when the layer is made (one pass over the roots' and leaves' blobs, no
//   reconstruction).
// A static tileset without a raster has none: one error line says what to give.

#include <string>

#include "terralod/core/progress.h"
#include "terralod/core/result.h"
#include "terralod/format/tileset_reader.h"
#include "terralod/materials/material.h"

namespace terralod::veg {

struct TilesetMaterialSource {
  std::string rasterPath;   ///< categorical raster; empty: the VIPM tileset's own materials
  std::string palettePath;  ///< JSON palette for the raster (palette.h); optional
};

/// `progress` counts the VIPM chunks read.
Result<MaterialMap> tilesetMaterials(const TilesetReader& tileset,
                                     const TilesetMaterialSource& source, Progress& progress);

}  // namespace terralod::veg
