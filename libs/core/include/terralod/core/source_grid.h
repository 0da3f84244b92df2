#pragma once
// Where a tileset's grid came from: the source raster's size, spacing and georeferencing as the
// tileset's metadata records them ("source": "geotransform", "crs_wkt"). Read by
// format (sourceGridOf), used to place a tileset on Earth (raster's EarthPlacement) and to
// resample other rasters onto its grid (materials' readMaterialRaster).

#include <array>
#include <cstdint>
#include <string>

namespace terralod {

struct SourceGrid {
  int32_t columns = 0, rows = 0;
  double spacingX = 1, spacingY = 1;     ///< local metres between grid points
  std::array<double, 6> geoTransform{};  ///< GDAL's, of the source raster
  bool hasGeoTransform = false;
  std::string crsWkt;  ///< empty: no CRS
};

}  // namespace terralod
