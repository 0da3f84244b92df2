#include "edit_source.h"

#include <filesystem>
#include <fstream>
#include <sstream>

#include "terralod/build/vipm_builder.h"
#include "terralod/build/vipm_rebuild.h"
#include "terralod/core/progress.h"
#include "terralod/format/terrain_edits_json.h"
#include "terralod/verify/verifier.h"

namespace terralod::cli {
namespace {

namespace fs = std::filesystem;

// The source the tileset was built from: --source, else the file its metadata names, next to
// the tileset or in the current directory.
Result<std::string> findSource(const TilesetReader& tileset, const EditSourceArgs& args) {
  if (!args.source.empty()) return args.source;
  const std::string& name = tileset.metadata().sourceFile;
  const std::string need =
      "edit needs the source's full-resolution heights (the chunks keep simplified meshes): "
      "give --source DEM";
  if (name.empty()) return makeError(args.tileset, need);
  for (const fs::path& dir : {fs::path(args.tileset).parent_path(), fs::current_path()}) {
    std::error_code ec;
    if (fs::is_regular_file(dir / name, ec)) return (dir / name).string();
  }
  return makeError(args.tileset, need + " (" + name +
                                     ", which it was built from, is neither next to it nor in "
                                     "the current directory)");
}

}  // namespace

Result<std::vector<TerrainEdit>> readEditScript(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return makeError(path, "cannot be read");
  std::ostringstream text;
  text << in.rdbuf();
  auto edits = parseTerrainEditScript(text.str(), path);
  if (!edits) return edits;
  if (edits->empty()) return makeError(path, "\"edits\" is empty: nothing to do");
  return edits;
}

Result<BuildOptions> editSourceOptions(const TilesetReader& tileset, const EditSourceArgs& args) {
  auto options = recordedVipmBuildOptions(tileset);
  if (!options) return options;
  auto source = findSource(tileset, args);
  if (!source) return source.error();
  const std::string& from = tileset.metadata().materialsSource;
  if (from != "classification" && args.materials.empty())
    return makeError(args.tileset, "was built with --materials " + from +
                                       ": give that raster again with --materials");
  if (from == "classification" && !args.materials.empty())
    return makeError(args.tileset,
                     "its materials were classified from the heights, not read "
                     "from a raster: leave out --materials");
  const TilesetHeader& h = tileset.header();
  const double verticalScale = options->dem.verticalScale;
  options->dem = tilesetDemOptions(tileset);
  options->dem.verticalScale = verticalScale;
  auto dem = DemReader::open(*source, options->dem);
  if (!dem) return dem.error();
  const DemInfo& info = (*dem)->info();
  if (uint32_t(info.columns) != h.sourceColumns || uint32_t(info.rows) != h.sourceRows)
    return makeError(*source, "is " + std::to_string(info.columns) + "x" +
                                  std::to_string(info.rows) + " samples but " + args.tileset +
                                  " was built from " + std::to_string(h.sourceColumns) + "x" +
                                  std::to_string(h.sourceRows));
  if (info.spacingX != h.spacingX || info.spacingY != h.spacingY)  // built with --spacing
    options->dem.spacing = std::array<double, 2>{h.spacingX, h.spacingY};
  options->input = *source;
  options->materialsPath = args.materials;
  options->palettePath = args.palette;
  options->threads = args.threads;
  return options;
}

Result<VipmChunkSet> openTilesetChunkSet(const TilesetReader& tileset, const std::string& path,
                                         const std::string& source) {
  auto options = editSourceOptions(tileset, {path, source, "", "", 0});
  if (!options) return options.error();
  options->reuse = path;  // every chunk kept: the set is the tileset
  TerminalProgress progress;
  return openVipmChunkSet(*options, progress);
}

}  // namespace terralod::cli
