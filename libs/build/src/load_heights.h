#pragma once
// Reads a whole raster into memory (voids still NaN), in strips, with progress.

#include "terralod/core/progress.h"
#include "terralod/core/result.h"
#include "terralod/raster/dem_reader.h"
#include "terralod/raster/heightfield.h"

namespace terralod {

Result<Heightfield> loadHeights(const DemReader& reader, Progress& progress);

}  // namespace terralod
