// terralod export TILESET [--level L] -o OUT.obj|OUT.ply|OUT.glb

#include <cstdio>
#include <filesystem>
#include <optional>

#include "cli_checks.h"
#include "commands.h"
#include "export_mesh.h"
#include "mesh_writers.h"
#include "terralod/core/atomic_file.h"

namespace terralod::cli {
namespace {

struct ExportOptions {
  std::string tileset, output;
  std::optional<int64_t> level;  // default: the finest
};

int exportLevel(const ExportOptions& options) {
  const auto format = meshFormatForPath(options.output);
  if (!format) {
    const std::string extension = std::filesystem::path(options.output).extension().string();
    return fail(options.output + ": unknown output format " +
                (extension.empty() ? "(no extension)" : "'" + extension + "'") +
                "; use .obj, .ply or .glb");
  }
  auto opened = TilesetReader::openPathOrUrl(options.tileset);  // a path or an http(s):// URL
  if (!opened) return fail(opened.error().message);
  const TilesetReader& tileset = **opened;
  const int64_t levels = tileset.header().levelCount;
  const int64_t level = options.level.value_or(levels - 1);
  if (level < 0 || level >= levels)
    return fail(options.tileset + ": no level " + std::to_string(level) +
                "; this tileset has levels 0 to " + std::to_string(levels - 1));

  // Fail on an unwritable output before the work, not after; nothing appears at the output
  // until the whole mesh is written.
  auto file = AtomicFile::create(options.output);
  if (!file) return fail(file.error().message);

  TerminalProgress progress;
  auto surface = gatherLevelSurface(tileset, uint32_t(level), progress);
  if (!surface) return fail(surface.error().message);
  if (surface->indices.empty())
    return fail(options.tileset + ": level " + std::to_string(level) + " has no triangles");
  // Neighbouring chunks should store the same height at a shared grid point; when they do
  // not, the welded mesh can only keep one of them, so say so rather than hide a crack.
  if (surface->heightMismatches) {
    char difference[32];
    std::snprintf(difference, sizeof(difference), "%.4g", surface->maxHeightDifference);
    warn(options.tileset + ": " + std::to_string(surface->heightMismatches) + " of " +
         std::to_string(surface->weldedVertices) + " vertices shared by chunks of level " +
         std::to_string(level) + " disagree in height, by up to " + difference +
         " m; kept the first chunk's");
  }

  const std::string description = "level " + std::to_string(level) + " of " +
                                  std::filesystem::path(options.tileset).filename().string();
  if (Status s = writeMesh(*surface, *format, description, *file); !s)
    return fail(s.error().message);
  if (Status s = file->commit(); !s) return fail(s.error().message);
  std::printf(
      "terralod: wrote %s: level %lld, %llu chunks, %llu vertices (%llu shared ones welded), "
      "%llu triangles, %llu bytes\n",
      options.output.c_str(), (long long)level, (unsigned long long)surface->chunks,
      (unsigned long long)surface->positions.size(), (unsigned long long)surface->weldedVertices,
      (unsigned long long)(surface->indices.size() / 3), (unsigned long long)file->bytesWritten());
  return 0;
}

}  // namespace

void addExportCommand(CLI::App& root, Runner& run) {
  auto* cmd = root.add_subcommand(
      "export",
      "Write the whole surface of one level as a mesh: every chunk of the level, unmorphed, "
      "without skirts, vertices shared by neighbouring chunks welded. Positions are float32 "
      "metres from the tileset's south-west sample. OBJ and PLY keep terralod's axes (x east, "
      "y north, z up); glTF is y up, so .glb gets (x, z, -y): x east, y up, -z north");
  auto options = std::make_shared<ExportOptions>();
  cmd->add_option("TILESET", options->tileset,
                  "Tileset: a .tlod file, or an http(s):// URL of one (read with range requests)")
      ->required();
  cmd->add_option("-o,--output", options->output,
                  "Mesh to write; the extension picks the format: .obj (text), .ply (binary) or "
                  ".glb (glTF 2.0 binary)")
      ->required();
  cmd->add_option("--level", options->level,
                  "Level to export, 0 (roots, coarsest) to levels-1 (default: the finest)")
      ->check(wholeNumber<int64_t>());
  cmd->footer(
      "Example:\n"
      "  terralod export dem.tlod --level 3 -o level3.glb\n");
  cmd->callback([&run, options] { run = [options] { return exportLevel(*options); }; });
}

}  // namespace terralod::cli
