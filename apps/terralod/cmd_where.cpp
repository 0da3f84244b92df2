// terralod where TILESET|EXPORT_DIR --eye X,Y,Z --target X,Y,Z: a terralod camera (local
// metres) on Earth, as a 3D Tiles client places it (scripts/cesium-screenshot.sh).

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>

#include "cli_values.h"
#include "commands.h"
#include "terralod/format/tileset_reader.h"
#include "terralod/tiles3d/earth_camera.h"

namespace terralod::cli {
namespace {

struct WhereOptions {
  std::string place, eye, target;
};

// The source grid of a 3D Tiles export (a directory, or its tileset.json) or of a tileset.
Result<SourceGrid> sourceGridAt(const std::string& place) {
  namespace fs = std::filesystem;
  std::error_code ec;
  std::string json = place;
  if (fs::is_directory(place, ec)) json = (fs::path(place) / "tileset.json").string();
  if (fs::path(json).extension() == ".json") {
    std::ifstream in(json, std::ios::binary);
    if (!in) return makeError(json, "cannot be read");
    std::stringstream text;
    text << in.rdbuf();
    const auto parsed = nlohmann::json::parse(text.str(), nullptr, false);
    if (parsed.is_discarded()) return makeError(json, "is not valid JSON");
    return tiles3d::exportedSourceGrid(parsed, json);
  }
  auto opened = TilesetReader::openPathOrUrl(place);
  if (!opened) return opened.error();
  return sourceGridOf((*opened)->header(), (*opened)->metadata());
}

int where(const WhereOptions& options) {
  const auto eye = parsePoint(options.eye, "--eye");
  if (!eye) return fail(eye.error().message);
  const auto target = parsePoint(options.target, "--target");
  if (!target) return fail(target.error().message);
  auto grid = sourceGridAt(options.place);
  if (!grid) return fail(grid.error().message);
  const tiles3d::ExportPlacement placed = tiles3d::placementOf(*grid, options.place);
  const auto camera = tiles3d::earthCamera(placed.placement, {eye->x, eye->y, eye->z},
                                           {target->x, target->y, target->z});
  if (!camera) return fail(camera.error().message);
  const nlohmann::json out = {{"eye_ecef", camera->eye},
                              {"direction_ecef", camera->direction},
                              {"up_ecef", camera->up},
                              {"longitude", camera->longitude},
                              {"latitude", camera->latitude},
                              {"height", camera->height},
                              {"placed_on_earth", placed.unplacedReason.empty()}};
  std::printf("%s\n", out.dump().c_str());
  return 0;
}

}  // namespace

void addWhereCommand(CLI::App& root, Runner& run) {
  auto* cmd = root.add_subcommand(
      "where",
      "Where a camera in a tileset's local metres is on Earth, as `export --format 3dtiles` "
      "places the tileset: prints one JSON line with the eye in Earth-centred, Earth-fixed "
      "metres (EPSG:4978), the unit view direction and up vector there, and the eye's WGS 84 "
      "longitude, latitude and height");
  auto options = std::make_shared<WhereOptions>();
  cmd->add_option("PLACE", options->place,
                  "A 3D Tiles export (its directory or tileset.json), or a tileset (.tlod or "
                  "http(s):// URL)")
      ->required();
  cmd->add_option("--eye", options->eye, "Eye position X,Y,Z in local metres (z up)")->required();
  cmd->add_option("--target", options->target, "Point looked at, X,Y,Z in local metres")
      ->required();
  cmd->footer(
      "Example (the camera of `terralod render zion.tlod --eye ... --target ...` in CesiumJS):\n"
      "  terralod where zion-3dtiles --eye 9000,-3000,4000 --target 17000,17000,1500\n");
  cmd->callback([&run, options] { run = [options] { return where(*options); }; });
}

}  // namespace terralod::cli
