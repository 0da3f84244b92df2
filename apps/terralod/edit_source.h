#pragma once
// What editing a VIPM tileset needs besides the tileset (terralod edit, bench --edit-script):
// its source raster, found as the metadata names it, and the options it was built with.

#include <string>
#include <vector>

#include "terralod/build/builder.h"
#include "terralod/build/vipm_chunk_set.h"
#include "terralod/format/tileset_reader.h"

namespace terralod::cli {

struct EditSourceArgs {
  std::string tileset;    ///< its path (the source is looked for beside it)
  std::string source;     ///< --source; empty: the file the metadata names
  std::string materials;  ///< --materials, for tilesets built with a categorical raster
  std::string palette;    ///< --palette
  unsigned threads = 0;
};

/// The strokes of an edit script (docs/format.md "Edits"); an empty list is refused.
Result<std::vector<TerrainEdit>> readEditScript(const std::string& path);

/// The options that build `tileset` again from its source: the recorded ones (and edits),
/// the source (`args.source`, else the file the metadata names, next to the tileset or in the
/// current directory), checked to be the size the tileset was built from. Output, reuse and new
/// edits are the caller's. Fails naming the tileset or the source.
Result<BuildOptions> editSourceOptions(const TilesetReader& tileset, const EditSourceArgs& args);

/// The tileset's chunk set for an editor (view --edit, bench --edit-script): its source read
/// again (`source`, else the file its metadata names), every chunk kept from the tileset.
Result<VipmChunkSet> openTilesetChunkSet(const TilesetReader& tileset, const std::string& path,
                                         const std::string& source);

}  // namespace terralod::cli
