#include "terralod/build/vipm_rebuild.h"

#include <cmath>
#include <nlohmann/json.hpp>

namespace terralod {

Result<BuildOptions> recordedVipmBuildOptions(const TilesetReader& tileset) {
  if (tileset.header().meshKind != MeshKind::kVipm)
    return makeError(tileset.name(),
                     "is not a VIPM tileset (edits apply to tilesets built with --kind vipm)");
  const nlohmann::json j = nlohmann::json::parse(tileset.metadataJson(), nullptr, false);
  const auto build = j.is_object() ? j.find("build") : j.end();
  auto number = [&](const char* key) -> std::optional<double> {
    if (build == j.end() || !build->is_object()) return std::nullopt;
    const auto v = build->find(key);
    if (v == build->end() || !v->is_number() || !std::isfinite(v->get<double>()))
      return std::nullopt;
    return v->get<double>();
  };
  const auto maxError = number("max_error");
  const auto level = number("zstd_level");
  if (!maxError || !level || *maxError <= 0.0)
    return makeError(tileset.name(),
                     "its metadata does not record how it was built (\"build\": \"max_error\", "
                     "\"zstd_level\"); rebuild it from the source");
  const TilesetMetadata& m = tileset.metadata();
  BuildOptions options;
  options.kind = TilesetKind::kVipm;
  options.maxError = *maxError;
  options.compressionLevel = int(*level);
  options.materialRules = m.materialRules ? MaterialRules::kOn : MaterialRules::kOff;
  options.dem.verticalScale = m.verticalScale;
  // "blot_error": metres, or null when built with --blot-error off; absent before it was
  // recorded (the default then).
  if (const auto blot = build->find("blot_error"); blot != build->end()) {
    if (blot->is_null())
      options.blotError = BlotError::off();
    else if (const auto metres = number("blot_error"))
      options.blotError = BlotError::metres(*metres);
  }
  options.edits = m.edits;
  // The levels above the 128-cell nodes, as the header has them.
  options.vipmUpperLevels = int32_t(tileset.header().levelCount) - 2;
  return options;
}

}  // namespace terralod
