#pragma once
// The list of edits as a JSON array, for the edit script and the tileset metadata alike.

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "terralod/core/result.h"
#include "terralod/core/terrain_edit.h"

namespace terralod {

/// Parses `list` (a JSON array of edits); errors read "<subject>: <where>[i]: <problem>".
Result<std::vector<TerrainEdit>> parseTerrainEditList(const nlohmann::json& list,
                                                      const std::string& subject,
                                                      const std::string& where);

nlohmann::json terrainEditList(const std::vector<TerrainEdit>& edits);

}  // namespace terralod
