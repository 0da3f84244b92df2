#pragma once
// verify for VIPM tilesets (docs/format.md "VIPM tilesets"): every LOD of every chunk against
// the source, the material rules, the parts, the fallback roots against their children's
// coarsest LODs, and the flanges against every neighbour's LODs. verifyTileset dispatches here.

#include "terralod/core/progress.h"
#include "terralod/format/tileset_reader.h"
#include "terralod/raster/dem_reader.h"
#include "terralod/raster/heightfield.h"
#include "terralod/verify/verifier.h"

namespace terralod {

/// How the tileset's source is opened (encoding, band, vertical scale from its metadata).

/// Fills `report` (levels, chunks, failures, vipm) for a VIPM tileset; fails only when the
/// source's materials cannot be read.
Status verifyVipmTileset(const TilesetReader& tileset, const Heightfield& heights,
                         const std::string& sourcePath, const VerifyOptions& options,
                         Progress& progress, VerifyReport& report);

}  // namespace terralod
