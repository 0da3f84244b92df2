#pragma once
// Terrain edits as JSON (docs/format.md "Edits"): the script `terralod edit --script` reads,
// {"edits": [{"brush": "raise|lower|smooth|paint", "center": [x, y], "radius": r,
// "amount": a, "material": id}, ...]}, and the same list a tileset's metadata keeps under
// "edits". Parsing refuses anything else, naming the entry and the field.

#include <string>
#include <string_view>
#include <vector>

#include "terralod/core/result.h"
#include "terralod/core/terrain_edit.h"

namespace terralod {

/// Parses an edit script; errors read "<subject>: edits[2]: <problem>".
Result<std::vector<TerrainEdit>> parseTerrainEditScript(std::string_view text,
                                                        const std::string& subject);

/// The script form of `edits` (what parseTerrainEditScript reads back exactly: numbers are
/// written with enough digits to round-trip).
std::string terrainEditScript(const std::vector<TerrainEdit>& edits);

}  // namespace terralod
