// terralod export TILESET [--level L | --error E] [--texture-size N | --no-texture] -o
// OUT.obj|OUT.ply|OUT.glb

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <span>

#include "cli_checks.h"
#include "commands.h"
#include "terralod/core/atomic_file.h"
#include "terralod/measure/export_mesh.h"
#include "terralod/measure/export_texture.h"
#include "terralod/measure/mesh_writers.h"
#include "terralod/tiles3d/export_3dtiles.h"

namespace terralod::cli {
namespace {

struct ExportOptions {
  std::string tileset, output;
  std::optional<int64_t> level;        // default: the finest
  std::optional<int64_t> textureSize;  // default: the full resolution, at most kDefaultTexture
  std::optional<double> error;         // VIPM tilesets: the allowed error (default: finest)
  bool noTexture = false;
  std::string format;           // "3dtiles": a 3D Tiles tileset in the directory -o names
  std::string tiling = "auto";  // 3dtiles: explicit, implicit or auto
};

int export3dTiles(const ExportOptions& options) {
  if (options.level || options.error || options.textureSize || options.noTexture)
    return fail(
        "--format 3dtiles exports every chunk with its own colour tile; --level, "
        "--error, --texture-size and --no-texture do not apply");
  auto opened = TilesetReader::openPathOrUrl(options.tileset);  // a path or an http(s):// URL
  if (!opened) return fail(opened.error().message);
  TerminalProgress progress;
  tiles3d::Export3dTilesOptions exportOptions;
  exportOptions.tiling = options.tiling == "explicit"   ? tiles3d::Tiling::kExplicit
                         : options.tiling == "implicit" ? tiles3d::Tiling::kImplicit
                                                        : tiles3d::Tiling::kAuto;
  auto summary = tiles3d::export3dTiles(**opened, options.output, exportOptions, progress, warn);
  if (!summary) return fail(summary.error().message);
  std::string tiling = "an explicit tree";
  if (summary->tiling == tiles3d::Tiling::kImplicit) {
    char text[160];
    std::snprintf(text, sizeof text,
                  "implicit quadtree tiling, %llu subtree files, content within %.2g m of its "
                  "implicit boxes",
                  (unsigned long long)summary->subtrees, summary->implicitBoxExcess);
    tiling = text;
  }
  std::printf(
      "terralod: wrote %s/tileset.json (%s): %llu tiles, %llu bytes of glTF (%llu of vertices "
      "and indices before meshopt), positions within %.3g m of their place%s\n",
      options.output.c_str(), tiling.c_str(), (unsigned long long)summary->tiles,
      (unsigned long long)summary->bytes, (unsigned long long)summary->uncompressedBytes,
      summary->maxQuantisationError, summary->placed ? "" : " (default placement)");
  return 0;
}

constexpr int64_t kDefaultTexture = 2048, kMaxTexture = 16384;

// A side file (texture, material library) beside the mesh: same name, another extension.
std::string besideOutput(const std::string& output, const char* extension) {
  return std::filesystem::path(output).replace_extension(extension).string();
}

int exportLevel(const ExportOptions& options) {
  if (options.tiling != "auto") return fail("--tiling goes with --format 3dtiles");
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
  const bool vipm = tileset.header().meshKind == MeshKind::kVipm;
  if (vipm && options.level)
    return fail(options.tileset + ": a VIPM tileset has no levels to export; use --error E");
  if (!vipm && options.error)
    return fail(options.tileset + ": --error applies to VIPM tilesets only; use --level L");
  if (options.error && !(std::isfinite(*options.error) && *options.error >= 0.0))
    return fail("--error " + std::to_string(*options.error) + ": must be 0 or more metres");
  const int64_t levels = tileset.header().levelCount;
  const int64_t level = options.level.value_or(levels - 1);
  if (level < 0 || level >= levels)
    return fail(options.tileset + ": no level " + std::to_string(level) +
                "; this tileset has levels 0 to " + std::to_string(levels - 1));

  if (options.textureSize && (*options.textureSize < 1 || *options.textureSize > kMaxTexture))
    return fail("--texture-size " + std::to_string(*options.textureSize) + ": must be 1 to " +
                std::to_string(kMaxTexture) + " pixels");
  // A VIPM tileset's texture blobs hold normal maps only: no colour image to export.
  const bool hasColor = tileset.header().textured() && !vipm;
  const bool textured = hasColor && !options.noTexture;
  if (options.textureSize && !hasColor)
    warn(options.tileset + (vipm ? ": a VIPM tileset has no colour texture; --texture-size ignored"
                                 : ": has no texture (built with --no-texture); --texture-size "
                                   "ignored"));

  // Fail on an unwritable output before the work, not after; nothing appears at the output
  // (nor beside it) until the whole mesh and its side files are written.
  auto file = AtomicFile::create(options.output);
  if (!file) return fail(file.error().message);
  // OBJ and PLY keep the texture in a PNG beside the mesh, OBJ its material in a .mtl.
  std::optional<AtomicFile> pngFile, mtlFile;
  if (textured && *format != MeshFormat::kGlb) {
    auto png = AtomicFile::create(besideOutput(options.output, ".png"));
    if (!png) return fail(png.error().message);
    pngFile.emplace(std::move(png).value());
    if (*format == MeshFormat::kObj) {
      auto mtl = AtomicFile::create(besideOutput(options.output, ".mtl"));
      if (!mtl) return fail(mtl.error().message);
      mtlFile.emplace(std::move(mtl).value());
    }
  }

  TerminalProgress progress;
  auto surface = vipm ? gatherVipmSurface(tileset, options.error.value_or(0.0), progress)
                      : gatherLevelSurface(tileset, uint32_t(level), progress);
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

  MeshExtras extras;
  extras.description = "level " + std::to_string(level) + " of " +
                       std::filesystem::path(options.tileset).filename().string();
  std::optional<ExportTexture> texture;
  if (textured) {
    auto full = fullTextureResolution(tileset);
    if (!full) return fail(full.error().message);
    const int64_t longSide = options.textureSize.value_or(
        std::clamp<int64_t>(int64_t(std::ceil(*full - 1e-6)), 1, kDefaultTexture));
    auto assembled = assembleTexture(tileset, uint32_t(longSide), progress);
    if (!assembled) return fail(assembled.error().message);
    texture = std::move(assembled).value();
    auto png = encodePng(*texture, pngFile ? pngFile->path() : options.output);
    if (!png) return fail(png.error().message);
    extras.png = std::move(png).value();
    if (pngFile) {
      extras.textureFile = std::filesystem::path(pngFile->path()).filename().string();
      if (Status s = pngFile->write(std::span<const uint8_t>(extras.png)); !s)
        return fail(s.error().message);
      extras.png.clear();  // written beside the mesh, not into it
    }
    if (mtlFile) {
      extras.materialLibrary = std::filesystem::path(mtlFile->path()).filename().string();
      if (Status s = mtlFile->write(objMaterialLibrary(extras.description, extras.textureFile)); !s)
        return fail(s.error().message);
    }
  }
  if (Status s = writeMesh(*surface, *format, extras, *file); !s) return fail(s.error().message);
  // Side files first, the mesh last: a mesh never refers to a file that is not there. Should
  // the mesh fail to appear, the side files just put in place go too.
  std::vector<std::string> committed;
  for (std::optional<AtomicFile>* side : {&pngFile, &mtlFile}) {
    if (!*side) continue;
    if (Status s = (*side)->commit(); !s) {
      for (const std::string& path : committed) std::filesystem::remove(path);
      return fail(s.error().message);
    }
    committed.push_back((*side)->path());
  }
  if (Status s = file->commit(); !s) {
    for (const std::string& path : committed) std::filesystem::remove(path);
    return fail(s.error().message);
  }
  std::printf(
      "terralod: wrote %s: level %lld, %llu chunks, %llu vertices (%llu shared ones welded), "
      "%llu triangles, %llu bytes\n",
      options.output.c_str(), (long long)level, (unsigned long long)surface->chunks,
      (unsigned long long)surface->positions.size(), (unsigned long long)surface->weldedVertices,
      (unsigned long long)(surface->indices.size() / 3), (unsigned long long)file->bytesWritten());
  if (texture) {
    const std::string where =
        pngFile ? "wrote " + pngFile->path() + " (" + std::to_string(pngFile->bytesWritten()) +
                      " bytes" + (mtlFile ? ", material in " + mtlFile->path() : "") + ")"
                : "embedded in " + options.output + " (" + std::to_string(extras.png.size()) +
                      " bytes of PNG)";
    std::printf("terralod: texture %ux%u from the colour of level %u (%.0f texels across): %s\n",
                texture->width, texture->height, texture->level, texture->levelTexels,
                where.c_str());
  } else {
    std::printf("terralod: no texture (%s)\n",
                options.noTexture ? "--no-texture" : "the tileset has none");
  }
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
  cmd->add_option("--error", options->error,
                  "VIPM tilesets: every leaf at the level drawn for this allowed error in metres, "
                  "without geomorphing (default 0: the finest)");
  auto* size = cmd->add_option("--texture-size", options->textureSize,
                               "Pixels along the longer side of the colour texture (the other in "
                               "proportion), sampled "
                               "from the coarsest level of the texture quadtree that has as many "
                               "(default: the tileset's "
                               "full resolution, at most 2048)")
                   ->check(wholeNumber<int64_t>());
  cmd->add_flag("--no-texture", options->noTexture,
                "Write no texture (normals and texture coordinates are written all the same)")
      ->excludes(size);
  cmd->footer(
      "Normals are unit, per vertex, angle-weighted from the exported triangles; texture "
      "coordinates run 0..1 over the data's extent. A textured tileset's colour goes with the "
      "mesh: embedded as PNG with a material in .glb; beside the mesh as NAME.png (and "
      "NAME.mtl) for .obj, as NAME.png named by a 'comment TextureFile' for .ply.\n\n"
      "Example:\n"
      "  terralod export dem.tlod --level 3 -o level3.glb\n");
  cmd->add_option("--format", options->format,
                  "3dtiles: write a 3D Tiles 1.1 tileset into the directory -o names (every chunk "
                  "a glTF, skirts included, placed on Earth from the source's georeferencing)")
      ->check(CLI::IsMember({"3dtiles"}));
  cmd->add_option("--tiling", options->tiling,
                  "--format 3dtiles: explicit (every tile in tileset.json), implicit (quadtree "
                  "tiling with subtree files), or auto: implicit from 4096 tiles on")
      ->capture_default_str()
      ->check(CLI::IsMember({"auto", "explicit", "implicit"}));
  cmd->callback([&run, options] {
    run = [options] {
      return options->format == "3dtiles" ? export3dTiles(*options) : exportLevel(*options);
    };
  });
}

}  // namespace terralod::cli
