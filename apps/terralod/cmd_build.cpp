// terralod build INPUT -o OUT.tlod

#include <cstdio>
#include <sstream>

#include "cli_checks.h"
#include "commands.h"
#include "staged_build.h"
#include "terralod/build/builder.h"
#include "terralod/core/batch_memory.h"

namespace terralod::cli {

void addBuildCommand(CLI::App& root, Runner& run) {
  auto* cmd =
      root.add_subcommand("build", "Preprocess an elevation raster into a chunk tree tileset");
  auto options = std::make_shared<BuildOptions>();
  auto encoding = std::make_shared<std::string>("none");
  auto spacing = std::make_shared<std::vector<double>>();
  cmd->add_option(
         "INPUT", options->input,
         "Elevation raster: anything GDAL reads (GeoTIFF, .hgt, .bt, .asc, netCDF, PNG...)")
      ->required();
  cmd->add_option("-o,--output", options->output, "Tileset to write (.tlod)")->required();
  cmd->add_option("--max-error", options->maxError,
                  "Geometric error of the finest level in metres; each coarser level doubles it")
      ->capture_default_str()
      ->check(positiveNumber());
  cmd->add_option("--encoding", *encoding,
                  "Height encoding of RGB web tiles: none, terrain-rgb, terrarium")
      ->capture_default_str()
      ->check(CLI::IsMember({"none", "terrain-rgb", "terrarium"}));
  cmd->add_option("--band", options->dem.band,
                  "Band holding the heights, 1-based (default 1; needed for rasters of several "
                  "8-bit bands, such as photos, which are refused otherwise)")
      ->check(wholeNumber<int>(1));
  cmd->add_option("--spacing", *spacing,
                  "Horizontal spacing DX[,DY] in metres (overrides georeferencing)")
      ->delimiter(',')
      ->expected(1, 2)
      ->check(positiveNumber());
  cmd->add_option("--vertical-scale", options->dem.verticalScale, "Multiply every height by S")
      ->capture_default_str()
      ->check(positiveNumber());
  cmd->add_option("--chunk-cells", options->chunkCells,
                  "Leaf chunk side in cells, a power of two up to 256 (default: from the terrain's "
                  "roughness, 64 to 256 cells; less for small rasters)")
      ->check(wholeNumber<int32_t>(0));
  cmd->add_option("--threads", options->threads, "Worker threads (default: all cores)")
      ->check(wholeNumber<unsigned>());
  cmd->add_option("--memory-mb", options->memoryMB,
                  "Memory budget for the input; larger rasters are read in windows")
      ->capture_default_str()
      ->check(wholeNumber<uint64_t>(1));
  cmd->add_option(
         "--zstd-level", options->compressionLevel,
         "zstd level for chunk data stored as meshoptimizer streams (1-22; bintree chunks are "
         "range-coded)")
      ->capture_default_str()
      ->check(wholeNumber(1, 22));
  cmd->add_option("--texture", options->textureImage,
                  "Image to drape (any georeferenced raster GDAL reads, in any CRS and "
                  "resolution); default: a generated colour (palette in metres, water, snow by "
                  "latitude, rock, occlusion)");
  auto* minTau =
      cmd->add_option("--min-tau", options->textureTau,
                      "Size textures so that no texel covers more than one pixel at this τ "
                      "(pixels) or below (the source's own resolution permitting)")
          ->capture_default_str()
          ->check(positiveNumber());
  auto noTexture = std::make_shared<bool>(false);
  cmd->add_flag("--no-texture", *noTexture,
                "Geometry only (a version 1 tileset; lit from the geometry's own normals)");
  auto perChunk = std::make_shared<bool>(false);
  cmd->add_flag("--texture-per-chunk", *perChunk,
                "Store every chunk's own texture, also where its parent's already holds the same "
                "texels (by default such chunks draw their parent's: levels capped at the "
                "source's resolution store their texels once; this shows what that saves)");
  auto bakeColour = std::make_shared<bool>(false);
  cmd->add_flag("--bake-colour", *bakeColour,
                "Store the generated colour as a colour texture (format version 5) instead of "
                "the shade layer the shader makes it from (version 6: water and occlusion only, "
                "at half the normal map's resolution; the colour itself comes from the drawn "
                "height, the normal map and the latitude's snow line)");
  auto mesher = std::make_shared<std::string>("rtin");
  cmd->add_option("--mesher", *mesher,
                  "Static chunks below the blocks: rtin (right-triangle bintree meshes, each "
                  "level refining its parent) or greedy (Delaunay meshes by greedy insertion "
                  "over every sample: fewer triangles for the same bound; a chunk's fully "
                  "morphed surface stays within 1/8 of its parent level's error of the parent's)")
      ->capture_default_str()
      ->check(CLI::IsMember({"rtin", "greedy"}));
  auto chunkCodec = std::make_shared<std::string>("bintree");
  cmd->add_option("--chunk-codec", *chunkCodec,
                  "How static chunks store their geometry: bintree (an RTIN chunk as its "
                  "bintree's split decisions and a height and delta residual per vertex, "
                  "range-coded: format version 7) "
                  "or meshopt (meshoptimizer's vertex and index streams, versions 4 to 6: for "
                  "readers of those versions). Greedy chunks are always meshopt")
      ->capture_default_str()
      ->check(CLI::IsMember({"bintree", "meshopt"}));
  auto kind = std::make_shared<std::string>("static");
  cmd->add_option("--kind", *kind,
                  "Chunk kind: static (chunked LOD, RTIN meshes) or vipm (a progressive mesh per "
                  "64-cell chunk with material-aware collapses; normal maps, no colour tiles)")
      ->capture_default_str()
      ->check(CLI::IsMember({"static", "vipm"}));
  cmd->add_option("--materials", options->materialsPath,
                  "vipm: categorical raster of material classes (any CRS; nearest-neighbour onto "
                  "the DEM; at most 8 classes); default: classify the DEM (water, grass, soil, "
                  "rock, snow)");
  cmd->add_option("--palette", options->palettePath,
                  "vipm: JSON palette naming the classes of --materials "
                  "({\"classes\": [{\"value\", \"name\", \"color\"}]})");
  auto noRules = std::make_shared<bool>(false);
  cmd->add_flag("--no-material-rules", *noRules,
                "vipm: collapse without the material rules (shows what they buy)");
  auto blotError = std::make_shared<std::string>();
  cmd->add_option(
         "--blot-error", *blotError,
         "vipm: leaves simplify with the material rules up to this error (metres, at least "
         "--max-error); beyond twice it the 128-cell roots draw instead, simplified further "
         "without the rules, their materials fading as they geomorph (blot chunks: far fewer "
         "triangles far away). Default: 4 x --max-error; off: leaves simplify as far as the "
         "rules allow")
      ->check(positiveNumberOr("off"));
  auto upperLevels = std::make_shared<std::string>();
  cmd->add_option("--upper-levels", *upperLevels,
                  "vipm: levels of nodes above the 128-cell roots (256, 512, ... cells), each "
                  "its children's coarsest levels joined and simplified further, so that the far "
                  "field draws few large nodes and only the top ones stay resident (maps too "
                  "large for their roots to stay in memory); 0 (a flat forest of roots) to 8, or "
                  "auto: as many as make one top node, at most 8. Default: auto for maps of "
                  "more than 256 roots (over 2048 cells a side), 0 below")
      ->check(CLI::Range(0, 8) | CLI::IsMember({"auto"}));
  cmd->add_option("--block-cells", options->blockCells,
                  "Side of the blocks both passes work in (a power of two, at least the leaf "
                  "chunk side): the unit of work of a staged build's jobs")
      ->capture_default_str()
      ->check(wholeNumber<int32_t>(1));
  auto staged = std::make_shared<StagedRequest>();
  cmd->add_option("--scheduler", staged->scheduler,
                  "Build in stages over --work-dir: local (every stage in this process), slurm "
                  "(submit the stages as Slurm jobs and follow them), or none (write the plan and "
                  "print the stage commands, for another scheduler)")
      ->check(CLI::IsMember({"local", "slurm", "none"}));
  cmd->add_option("--work-dir", staged->work,
                  "Staged builds: a directory every job can read and write (shared between "
                  "nodes); emptied and removed when the build succeeds");
  cmd->add_option("--jobs", staged->jobs,
                  "Staged builds: block jobs of passes 1 and 2 (default: one per block, at most "
                  "64)")
      ->check(wholeNumber<int>(1));
  cmd->add_option("--sbatch-args", staged->sbatchArgs,
                  "--scheduler slurm: more sbatch options for every job (e.g. \"--partition=big "
                  "--time=2:00:00\")");
  cmd->add_option("--retries", staged->retries,
                  "--scheduler slurm: times a killed or lost job task is submitted again")
      ->capture_default_str()
      ->check(wholeNumber(0, 10));
  auto verbose = std::make_shared<bool>(false);
  cmd->add_flag("--verbose", *verbose,
                "Print how the build went: passes, triangles scanned exactly");
  cmd->footer(
      "Examples:\n"
      "  terralod build dem.tif -o dem.tlod\n"
      "  terralod build dem.tif --texture ortho.tif --max-error 0.5 -o dem.tlod\n"
      "  terralod build tile.png --encoding terrarium -o tile.tlod\n"
      "  terralod build scan.tif --band 2 -o scan.tlod\n"
      "  terralod build dem.tif --kind vipm --materials classes.tif -o dem.tlod\n"
      "  terralod build big.tif -o big.tlod --scheduler slurm --work-dir /shared/w --jobs 64\n"
      "Errors: one line \"terralod: error: <file>: <problem>\", exit status 1, no output left "
      "behind.\n");
  cmd->callback([&run, options, encoding, spacing, verbose, noTexture, perChunk, kind, noRules,
                 minTau, blotError, upperLevels, staged, mesher, bakeColour, chunkCodec] {
    run = [options, encoding, spacing, verbose, noTexture, perChunk, kind, noRules, minTau,
           blotError, upperLevels, staged, mesher, bakeColour, chunkCodec] {
      keepFreedMemoryForReuse();
      if (*noTexture && !options->textureImage.empty())
        return fail("--texture and --no-texture contradict each other");
      options->textures = !*noTexture;
      if (*perChunk && *noTexture)
        return fail("--texture-per-chunk and --no-texture contradict each other");
      options->textureSharing = *perChunk ? TextureSharing::kEveryChunk : TextureSharing::kInherit;
      options->mesher = *mesher == "greedy" ? MeshMethod::kGreedy : MeshMethod::kRtin;
      options->chunkCodec = *chunkCodec == "meshopt" ? ChunkCodec::kMeshopt : ChunkCodec::kBintree;
      if (*bakeColour && *noTexture)
        return fail("--bake-colour and --no-texture contradict each other");
      if (*bakeColour && !options->textureImage.empty())
        return fail(
            "--bake-colour applies to the generated colour (a draped image is stored as "
            "it is)");
      if (*bakeColour && *kind == "vipm")
        return fail(
            "--bake-colour does not apply to --kind vipm (colour comes from the materials)");
      options->generatedColour = *bakeColour ? GeneratedColour::kBaked : GeneratedColour::kShader;
      if (*kind == "vipm") {
        if (options->mesher != MeshMethod::kRtin)
          return fail("--mesher applies to --kind static only");
        if (*chunkCodec != "bintree") return fail("--chunk-codec applies to --kind static only");
        if (!options->textureImage.empty())
          return fail("--texture does not apply to --kind vipm (colour comes from the materials)");
        if (minTau->count() > 0)
          return fail(
              "--min-tau does not apply to --kind vipm (its normal maps have one texel per grid "
              "point)");
        if (*perChunk)
          return fail(
              "--texture-per-chunk does not apply to --kind vipm (its normal maps are per chunk)");
        if (*noTexture)
          return fail(
              "--no-texture does not apply to --kind vipm (its chunks are lit by their stored "
              "normal maps)");
        options->kind = TilesetKind::kVipm;
        options->textures = false;  // no colour tiles: normal maps only (vipm_builder.h)
        options->materialRules = *noRules ? MaterialRules::kOff : MaterialRules::kOn;
        if (*blotError == "off") {
          options->blotError = BlotError::off();
        } else if (!blotError->empty()) {
          options->blotError = BlotError::metres(std::stod(*blotError));  // checked
        }
        if (options->blotError.leafError(options->maxError) < options->maxError)
          return fail("--blot-error must be at least --max-error");
        if (*upperLevels == "auto") {
          options->vipmUpperLevels = kVipmUpperLevelsAuto;
        } else if (!upperLevels->empty()) {
          options->vipmUpperLevels = std::stoi(*upperLevels);  // checked
        }
      } else {
        for (auto [given, name] : {std::pair{!options->materialsPath.empty(), "--materials"},
                                   std::pair{!options->palettePath.empty(), "--palette"},
                                   std::pair{*noRules, "--no-material-rules"},
                                   std::pair{!blotError->empty(), "--blot-error"},
                                   std::pair{!upperLevels->empty(), "--upper-levels"}})
          if (given) return fail(std::string(name) + " applies to --kind vipm only");
      }
      if (!options->palettePath.empty() && options->materialsPath.empty())
        return fail("--palette names the classes of --materials, which is missing");
      options->dem.encoding = *parseHeightEncoding(*encoding);
      if (options->dem.band != 0 && options->dem.encoding != HeightEncoding::kPlain)
        return fail(
            "--band and --encoding contradict each other (RGB-encoded heights use bands "
            "1 to 3)");
      if (!spacing->empty())
        options->dem.spacing = std::array<double, 2>{(*spacing)[0], spacing->back()};
      if (staged->scheduler.empty() != staged->work.empty())
        return fail("--scheduler and --work-dir go together (a staged build)");
      if (staged->scheduler.empty())
        for (auto [given, name] : {std::pair{staged->jobs != 0, "--jobs"},
                                   std::pair{!staged->sbatchArgs.empty(), "--sbatch-args"}})
          if (given) return fail(std::string(name) + " applies to staged builds (--scheduler)");
      if (!staged->sbatchArgs.empty() && staged->scheduler != "slurm")
        return fail("--sbatch-args applies to --scheduler slurm");
      TerminalProgress progress;
      if (staged->scheduler == "none") return planForOtherScheduler(*options, *staged);
      auto summary = staged->scheduler.empty()
                         ? buildTileset(*options, progress, warn)
                         : buildStaged(*options, *staged, progress,
                                       *verbose ? StageReport::kFigures : StageReport::kQuiet);
      if (!summary) return fail(summary.error().message);
      const BuildSummary& s = *summary;
      if (!staged->scheduler.empty()) {
        std::printf(
            "terralod: wrote %s: %d levels, %llu chunks, %llu triangles, %.2f MB, %.2f s "
            "(staged: %s)\n",
            options->output.c_str(), s.levels, (unsigned long long)s.chunks,
            (unsigned long long)s.triangles, s.fileBytes / 1e6, s.totalSeconds,
            staged->scheduler.c_str());
        return 0;
      }
      // A streamed build reads as it goes: its reading time is inside the two passes.
      char read[64] = "streamed";
      if (s.readOnce) std::snprintf(read, sizeof read, "streamed, read once");
      if (s.keptSamples)
        std::snprintf(read, sizeof read, "streamed, read once, %.1f %% of it kept",
                      100.0 * double(s.keptSamples) / double(s.sourceSamples));
      if (!s.streamed) std::snprintf(read, sizeof read, "read %.2f s", s.loadSeconds);
      const uint64_t geometryBytes = s.fileBytes - s.textureBytes;
      char texture[64] = "";
      if (s.textureBytes)
        std::snprintf(texture, sizeof texture, " + %.2f MB textures", s.textureBytes / 1e6);
      char phases[64];
      if (options->kind == TilesetKind::kVipm)
        std::snprintf(phases, sizeof phases, "chunks %.2f s", s.meshSeconds);
      else
        std::snprintf(phases, sizeof phases, "errors %.2f s, meshes %.2f s", s.errorSeconds,
                      s.meshSeconds);
      std::printf(
          "terralod: wrote %s: %d levels, %llu chunks, %llu triangles, %llu vertices, %.2f MB "
          "geometry (%.2f bytes/vertex, %.3f bytes/sample)%s, %llu voids filled, %.2f s (%s, "
          "%s)\n",
          options->output.c_str(), s.levels, (unsigned long long)s.chunks,
          (unsigned long long)s.triangles, (unsigned long long)s.vertices, geometryBytes / 1e6,
          s.vertices ? double(geometryBytes) / double(s.vertices) : 0.0,
          double(geometryBytes) / double(s.sourceSamples), texture,
          (unsigned long long)s.filledVoids, s.totalSeconds, read, phases);
      if (options->kind == TilesetKind::kVipm)
        std::printf(
            "terralod: vipm: %u materials, %llu collapses, %.1f ms CPU per leaf chunk (median; max "
            "%.1f ms)\n",
            s.materials, (unsigned long long)s.collapses, s.chunkSecondsMedian * 1e3,
            s.chunkSecondsMax * 1e3);
      if (*verbose)
        std::printf(
            "terralod: %s input, %d error pass(es), %llu triangles scanned exactly, %llu "
            "settled by bounds\n",
            s.streamed ? "streamed" : "in-memory", s.errorPasses,
            (unsigned long long)s.trianglesScanned, (unsigned long long)s.trianglesBounded);
      return 0;
    };
  });
}

}  // namespace terralod::cli
