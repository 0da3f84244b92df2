#pragma once
// What rebuilding a VIPM tileset needs to know about how it was built (`terralod edit`
// rebuilds with the edits applied; a rebuild with no new edit writes the same bytes).

#include "terralod/build/builder.h"
#include "terralod/format/tileset_reader.h"

namespace terralod {

/// The options the tileset's metadata records ("build": max_error, blot_error,
/// material_rules, zstd_level, vertical_scale; "edits"), as BuildOptions for --kind vipm.
/// input, output, the DEM's encoding and band, --materials and --palette are the caller's.
/// Fails naming the tileset when it is not a VIPM tileset or the record is incomplete.
Result<BuildOptions> recordedVipmBuildOptions(const TilesetReader& tileset);

}  // namespace terralod
