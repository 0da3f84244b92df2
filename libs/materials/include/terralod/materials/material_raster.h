#pragma once
// Materials from a categorical raster: any raster GDAL reads, in any CRS, resampled
// nearest-neighbour onto the DEM's grid (each grid point samples the class under its pixel
// centre, through GDAL's warper with an exact transformation).
//
// Classes are the distinct values of band 1 found over the DEM (its nodata excluded), sorted
// ascending; material index i is the i-th of them and its id is the value. Names and colours
// come from, in order: the JSON palette if given (every value used must be in it; unused
// palette entries are dropped); else the raster's own colour table, category names or raster
// attribute table (a Name column, a value column and Red/Green/Blue columns), or the band
// metadata items CLASS_NAME_<value> that `terralod classify` writes; else "class <value>" and
// distinctColor().
//
// When the raster or the DEM has no CRS (but both have a geotransform), both are taken to be in
// the same one.
//
// Grid points the raster does not cover, or where it holds nodata, take the class of the
// nearest covered point (in 4-connected steps over the grid; ties go to the first reached in
// scan order, so the result is deterministic).
//
// Refused, each with one line naming the file: a missing file or one GDAL cannot read as a
// raster; a raster that covers none of the DEM; continuous data (a non-integer value, or more
// than 256 distinct values over the DEM); class values outside 0..255; more than
// kMaxMaterials classes over the DEM; palette errors (see palette.h) and a value the palette
// lacks; a georeferenced raster on a DEM without georeferencing (or the reverse, unless both
// lack it and have the same size, when raster pixel (c, r) is grid point (c, rows-1-r)).

#include <string>

#include "terralod/core/result.h"
#include "terralod/core/source_grid.h"
#include "terralod/materials/material.h"
#include "terralod/raster/dem_reader.h"

namespace terralod {

struct MaterialRasterOptions {
  std::string palettePath;  ///< JSON palette (palette.h); empty: from the raster itself
};

/// More distinct values than this over the DEM: continuous data, not classes.
constexpr int kMaxDistinctValuesForClasses = 256;

/// Onto the grid `dem` describes (its columns, rows, georeferencing; its path names it in
/// errors): a DEM's own, or a tileset's source grid recorded in its metadata.
Result<MaterialMap> readMaterialRaster(const std::string& path, const DemInfo& dem,
                                       const MaterialRasterOptions& options = {});
/// Onto a tileset's source grid (`gridName` names it in errors).
Result<MaterialMap> readMaterialRaster(const std::string& path, const SourceGrid& grid,
                                       const std::string& gridName,
                                       const MaterialRasterOptions& options = {});
/// Onto a DEM's grid.
inline Result<MaterialMap> readMaterialRaster(const std::string& path, const DemReader& dem,
                                              const MaterialRasterOptions& options = {}) {
  return readMaterialRaster(path, dem.info(), options);
}

}  // namespace terralod
