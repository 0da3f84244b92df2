#pragma once
// The tileset's metadata JSON (docs/format.md, "Metadata"), parsed and validated once when a
// tileset is opened, as the typed values readers use: how the source was read (for verify),
// and each level's texture tile sizes (for the renderer's mip placement and for export).
// What nobody reads stays in the JSON (`terralod info` prints it whole).

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "terralod/core/result.h"
#include "terralod/format/tileset_format.h"

namespace terralod {

/// One level's texture tiles (texels a side, 2^k + 1).
struct TextureLevelSizes {
  uint32_t color = 0;
  uint32_t normal = 0;
  friend bool operator==(const TextureLevelSizes&, const TextureLevelSizes&) = default;
};

struct TilesetMetadata {
  /// "source": "encoding" as written ("none", "terrain-rgb", "terrarium").
  std::string sourceEncoding = "none";
  /// "source": "band", recorded only for multi-band sources.
  std::optional<int> sourceBand;
  /// "build": "vertical_scale".
  double verticalScale = 1.0;
  /// "texture": "levels", root level first: one per level, or empty when the tileset is
  /// untextured or was written before the sizes were recorded.
  std::vector<TextureLevelSizes> textureLevels;
};

/// Parses and validates `json` for a tileset with `header`; `subject` names the file in
/// errors. Refuses what is not a JSON object, and fields of the wrong type or out of range
/// (a texture size that is not 2^k + 1 in [2, 4097], a level list not one per level).
Result<TilesetMetadata> parseTilesetMetadata(std::string_view json, const TilesetHeader& header,
                                             const std::string& subject);

}  // namespace terralod
