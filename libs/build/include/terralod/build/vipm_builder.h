#pragma once
// `terralod build --kind vipm`: a DEM (and optionally a categorical raster of materials) in, a
// VIPM tileset out (docs/format.md "VIPM tilesets"; architecture.md "VIPM chunks").
//
// Stages: read the DEM whole and fill its voids; materials (readMaterialRaster with
// --materials, else classifyDem); one zStep for the tileset (vipmTilesetZStep over the largest
// root height range); the leaves in parallel (buildVipmLeaf); the roots from their children's
// coarsest levels (joinCoarsest); flange depths; blobs appended in node order, then the node
// table, header and metadata. The output depends only on the inputs and options, never on the
// thread count.

#include <functional>
#include <string>

#include "terralod/build/builder.h"
#include "terralod/build/vipm_chunk_set.h"

namespace terralod {

/// The chunk set buildVipmTileset writes: the source read whole (voids filled, options.edits
/// applied), its materials, every chunk built or kept (options.reuse). What an editor holds.
Result<VipmChunkSet> openVipmChunkSet(const BuildOptions& options, Progress& progress);

/// Writes `set` as a tileset at `output` (atomically: the file appears complete or not at all),
/// its strokes recorded: the bytes buildVipmTileset writes for the source with those strokes.
Status writeVipmTileset(const VipmChunkSet& set, const std::string& output);

Result<BuildSummary> buildVipmTileset(const BuildOptions& options, Progress& progress,
                                      const std::function<void(const std::string&)>& warn);

}  // namespace terralod
