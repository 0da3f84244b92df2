#include "vipm_chunk_reuse.h"

#include <filesystem>
#include <nlohmann/json.hpp>

#include "terralod/build/vipm_rebuild.h"

namespace terralod {
namespace {

// Whether `old` was built from this source with these options, but for the strokes after its
// own (its recorded "edits" a prefix of options.edits).
bool sameBuild(const TilesetReader& old, const BuildOptions& options, const DemInfo& info,
               const TreeLayout& layout, double zStep) {
  const TilesetHeader& h = old.header();
  if (h.meshKind != MeshKind::kVipm || h.sourceColumns != uint32_t(info.columns) ||
      h.sourceRows != uint32_t(info.rows) || h.spacingX != info.spacingX ||
      h.spacingY != info.spacingY || h.levelCount != uint32_t(layout.levelCount()) ||
      h.rootCells != uint32_t(layout.rootCells) ||
      h.levelError[size_t(layout.depth)] != options.maxError)
    return false;
  auto recorded = recordedVipmBuildOptions(old);
  if (!recorded) return false;
  const std::string materials =
      options.materialsPath.empty()
          ? "classification"
          : std::filesystem::path(options.materialsPath).filename().string();
  if (recorded->maxError != options.maxError ||
      recorded->compressionLevel != options.compressionLevel ||
      recorded->materialRules != options.materialRules ||
      recorded->blotError.leafError(options.maxError) !=
          options.blotError.leafError(options.maxError) ||
      recorded->dem.verticalScale != options.dem.verticalScale ||
      old.metadata().materialsSource != materials)
    return false;
  const auto& before = recorded->edits;
  if (before.size() > options.edits.size() ||
      !std::equal(before.begin(), before.end(), options.edits.begin()))
    return false;
  const nlohmann::json j = nlohmann::json::parse(old.metadataJson(), nullptr, false);
  if (!j.is_object() || !j.contains("build") || !j["build"].is_object()) return false;
  const nlohmann::json& build = j["build"];
  return build.contains("z_step") && build["z_step"].is_number() &&
         build["z_step"].get<double>() == zStep;
}

}  // namespace

std::optional<VipmChunkReuse> VipmChunkReuse::open(const BuildOptions& options, const DemInfo& info,
                                                   const TreeLayout& layout, double zStep) {
  if (options.reuse.empty()) return std::nullopt;
  auto old = TilesetReader::openFile(options.reuse);
  if (!old || !sameBuild(**old, options, info, layout, zStep)) return std::nullopt;
  VipmChunkReuse reuse;
  const size_t kept = (*old)->metadata().edits.size();
  for (size_t i = kept; i < options.edits.size(); ++i)
    reuse.mStrokes.push_back(
        editWindow(options.edits[i], info.spacingX, info.spacingY, info.columns, info.rows));
  reuse.mOld = std::move(*old);
  return reuse;
}

std::optional<NodeBytes> VipmChunkReuse::clean(uint32_t index, int32_t x0, int32_t y0,
                                               int32_t width, int32_t height) const {
  for (const GridWindow& w : mStrokes)
    if (windowMeets(w, x0, y0, width, height, 1)) return std::nullopt;
  if (index >= mOld->nodes().size()) return std::nullopt;
  auto bytes = mOld->readNode(index);
  if (!bytes) return std::nullopt;
  return std::move(*bytes);
}

}  // namespace terralod
