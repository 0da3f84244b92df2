// terralod vegetation bake|info|points|render-tile: the vegetation tiles of
// papers/tiling-layered-depth-images.md (docs/architecture.md, "Vegetation").

#include <cstdio>

#include "cli_checks.h"
#include "commands.h"
#include "terralod/core/atomic_file.h"
#include "terralod/core/parallel.h"
#include "terralod/vegetation/vegetation_bake.h"
#include "vegetation_commands.h"

namespace terralod::cli {
namespace {

std::string sceneList() {
  std::string s;
  for (const std::string& n : veg::vegetationSceneNames()) s += (s.empty() ? "" : "|") + n;
  return s;
}

void addBake(CLI::App& parent, Runner& run) {
  auto* cmd = parent.add_subcommand(
      "bake",
      "Place plants in the 8 Wang prototiles and bake their layered depth images (7 resolutions "
      "x 8 directions each) by ray casting");
  auto o = std::make_shared<VegetationBakeOptions>();
  cmd->add_option("--scene", o->scene, "Scene: " + sceneList())->capture_default_str();
  cmd->add_option("--tile-size", o->tileSize,
                  "Tile side in metres (default: the scene's, 4.4 for sunflowers, 2 for meadow)")
      ->check(numberBetween(0.5, 50));
  cmd->add_option("--seed", o->seed, "Seed of the plants and their placement")
      ->capture_default_str()
      ->check(wholeNumber<uint64_t>());
  cmd->add_option("--threads", o->threads, "Worker threads (default: all cores)")
      ->check(wholeNumber<unsigned>(1, 1024));
  cmd->add_option("--finest", o->finest,
                  "Pixels across the finest LDIs (default 468, the paper's); the coarser six "
                  "scale with it, as do their ring distances")
      ->check(wholeNumber<uint32_t>(16, 2048));
  cmd->add_option("--rays-per-pixel", o->raysPerPixel, "Jittered rays a pixel (a square number)")
      ->capture_default_str()
      ->check(CLI::IsMember({1, 4, 9, 16}));
  cmd->add_option("--occlusion-rays", o->occlusionRays,
                  "Ambient-occlusion rays a layer (0: sky light unshadowed)")
      ->capture_default_str()
      ->check(wholeNumber<uint32_t>(0, 256));
  cmd->add_option("-o,--output", o->output, ".tlv file to write")->required();
  cmd->footer(
      "Examples:\n  terralod vegetation bake --scene sunflowers -o sunflowers.tlv\n"
      "  terralod vegetation bake --scene meadow --finest 64 --rays-per-pixel 1 -o quick.tlv\n");
  cmd->callback([&run, o] { run = [o] { return runVegetationBake(*o); }; });
}

void addInfo(CLI::App& parent, Runner& run) {
  auto* cmd = parent.add_subcommand("info", "Describe a .tlv file: tiles, plants, LDIs, bytes");
  auto path = std::make_shared<std::string>();
  auto json = std::make_shared<bool>(false);
  cmd->add_option("file", *path, ".tlv file or http(s):// URL")->required();
  cmd->add_flag("--json", *json, "Print JSON");
  cmd->callback(
      [&run, path, json] { run = [path, json] { return runVegetationInfo(*path, *json); }; });
}

void addPoints(CLI::App& parent, Runner& run) {
  auto* cmd = parent.add_subcommand(
      "points",
      "Lay a Wang tiling and write every plant and every tile of it as CSV, with a "
      "check of the spacing (overlaps, density near edges and corners)");
  auto o = std::make_shared<VegetationPointsOptions>();
  cmd->add_option("file", o->input, ".tlv file or http(s):// URL")->required();
  cmd->add_option("--tiling", o->tiling, "Tiles across x tiles up, e.g. 64x64")
      ->capture_default_str();
  cmd->add_option("--seed", o->seed, "Seed of the tiling")
      ->capture_default_str()
      ->check(wholeNumber<uint64_t>());
  cmd->add_option("--csv", o->pointsCsv,
                  "Plants: x,y,tight_radius,packing_radius,species,version,tile_x,tile_y");
  cmd->add_option("--tiles-csv", o->tilesCsv,
                  "Tiles: tile_x,tile_y,prototile,north,east,south,west");
  cmd->add_option("--density-png", o->densityPng,
                  "Plant density over the tile square, folded from the whole tiling (mean: grey, "
                  "none: black, twice the mean: white), tile edges outlined");
  cmd->callback([&run, o] { run = [o] { return runVegetationPoints(*o); }; });
}

void addRenderTile(CLI::App& parent, Runner& run) {
  auto* cmd = parent.add_subcommand(
      "render-tile",
      "Picture of one prototile: one of its LDIs at its own resolution (--view ldi), "
      "its plants ray cast from above in their context (--view top), or its directional "
      "textures for beyond the LDI range (--view textures: a row per elevation, a column "
      "per direction)");
  auto o = std::make_shared<RenderTileOptions>();
  cmd->add_option("file", o->input, ".tlv file or http(s):// URL")->required();
  cmd->add_option("--tile", o->tile, "Prototile 0-7, or all: the 8 on one sheet, 4 a row")
      ->capture_default_str()
      ->check(CLI::IsMember({"0", "1", "2", "3", "4", "5", "6", "7", "all"}));
  cmd->add_option("--resolution", o->resolution, "Resolution 0-6 (0: the finest, nearest ring)")
      ->capture_default_str()
      ->check(wholeNumber<int>(0, 6));
  cmd->add_option("--direction", o->direction, "View direction 0-7 (0: looking north, 2: east)")
      ->capture_default_str()
      ->check(wholeNumber<int>(0, 7));
  cmd->add_option("--view", o->view, "ldi, top or textures")
      ->capture_default_str()
      ->check(CLI::IsMember({"ldi", "top", "textures"}));
  cmd->add_option("-o,--output", o->output, "PNG or JPEG to write")->required();
  cmd->callback([&run, o] { run = [o] { return runVegetationRenderTile(*o); }; });
}

void addPlacement(CLI::App& parent, Runner& run) {
  auto* cmd = parent.add_subcommand(
      "placement",
      "Place a scene's plants for one or more seeds without baking, lay each over a "
      "tiling and report the spacing: overlaps, and density near edges and corners "
      "against the tile interior's, averaged over the seeds");
  auto o = std::make_shared<VegetationPlacementOptions>();
  cmd->add_option("--scene", o->scene, "Scene: " + sceneList())->capture_default_str();
  cmd->add_option("--tile-size", o->tileSize, "Tile side in metres (default: the scene's)")
      ->check(numberBetween(0.5, 50));
  cmd->add_option("--seed", o->seed, "First seed")
      ->capture_default_str()
      ->check(wholeNumber<uint64_t>());
  cmd->add_option("--seeds", o->seeds, "Seeds to place and average over")
      ->capture_default_str()
      ->check(wholeNumber<uint32_t>(1, 10000));
  cmd->add_option("--tiling", o->tiling, "Tiles across x tiles up")->capture_default_str();
  cmd->add_option("--density-png", o->densityPng, "Density over the tile square (as in points)");
  cmd->add_flag("--plain", o->plain,
                "The paper's plain round-robin: no pass over the edges and corners first");
  cmd->add_option("--band", o->band,
                  "Metres from an edge counted as near it (default: twice the largest packing "
                  "radius)")
      ->check(positiveNumber());
  cmd->callback([&run, o] { run = [o] { return runVegetationPlacement(*o); }; });
}

void addTiling(CLI::App& parent, Runner& run) {
  auto* cmd = parent.add_subcommand(
      "tiling",
      "Measure how random the stochastic Wang tiling looks (same-prototile neighbours, "
      "autocorrelation) beside Robinson-style hierarchical structure, as numbers and as "
      "the paper's Figure 4");
  auto o = std::make_shared<VegetationTilingOptions>();
  cmd->add_option("--size", o->size, "Tiles a side")
      ->capture_default_str()
      ->check(wholeNumber<uint32_t>(8, 4096));
  cmd->add_option("--seed", o->seed, "Seed of the tiling")
      ->capture_default_str()
      ->check(wholeNumber<uint64_t>());
  cmd->add_option("-o,--output", o->output, "PNG of the comparison");
  cmd->add_flag("--json", o->json, "Print JSON");
  cmd->add_option("--time", o->timeSize,
                  "Also lay an N x N tiling by the scanline and look every tile up alone, timed "
                  "(one byte a tile: 10000 takes 100 MB)")
      ->check(wholeNumber<uint32_t>(1, 30000));
  cmd->callback([&run, o] { run = [o] { return runVegetationTiling(*o); }; });
}

}  // namespace

int runVegetationBake(const VegetationBakeOptions& o) {
  auto scene = veg::vegetationScene(
      o.scene, o.tileSize > 0 ? std::optional(o.tileSize) : std::nullopt, o.seed);
  if (!scene) return fail(scene.error().message);
  if (o.finest) veg::scaleResolutions(scene->rig, o.finest);
  scene->sampling.raysPerPixel = o.raysPerPixel;
  scene->lighting.occlusionRays = o.occlusionRays;
  {  // Refuse an unwritable output now, not after the bake.
    auto probe = AtomicFile::create(o.output);
    if (!probe) return fail(probe.error().message);
  }
  TerminalProgress progress;
  const veg::VegetationBake baked =
      veg::bakeVegetation(*scene, o.threads ? o.threads : hardwareThreads(), progress);
  if (Status written = veg::writeVegetationFile(o.output, baked.header, baked.ldis); !written)
    return fail(written.error().message);
  uint64_t bytes = 0, pixels = 0, objects = 0;
  for (const veg::EncodedLdi& l : baked.ldis) bytes += l.blob.size(), pixels += l.depthPixels;
  for (const auto& t : baked.header.tiles)
    for (const auto& p : t.objects) objects += veg::centredIn(p, baked.header.settings.tileSize);
  const auto& s = baked.header.settings;
  std::printf(
      "terralod: wrote %s: scene %s, %g m tiles, %llu plants in 8 tiles, %d LDIs, %.1f M depth "
      "pixels, %.1f MB of LDIs, %.1f M rays in %.1f s (%.2f M rays/s)\n",
      o.output.c_str(), s.scene.c_str(), s.tileSize, (unsigned long long)objects, veg::kLdiCount,
      pixels / 1e6, bytes / 1e6, s.raysCast / 1e6, s.bakeSeconds, s.raysCast / 1e6 / s.bakeSeconds);
  return 0;
}

void addVegetationCommand(CLI::App& root, Runner& run) {
  auto* cmd = root.add_subcommand(
      "vegetation",
      "Vegetation tiles: plants placed in 8 stochastic Wang tiles and baked into multiresolution "
      "view-dependent layered depth images");
  cmd->require_subcommand(1, 1);
  addBake(*cmd, run);
  addInfo(*cmd, run);
  addPoints(*cmd, run);
  addRenderTile(*cmd, run);
  addTiling(*cmd, run);
  addPlacement(*cmd, run);
}

}  // namespace terralod::cli
