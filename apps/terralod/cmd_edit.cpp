// terralod edit: brush strokes from a script applied to a VIPM tileset, headless. The tileset
// is rebuilt from its source with every recorded stroke and the new ones applied, and replaces
// the old file only once complete (an interrupted edit leaves the old tileset as it was).
#include <cstdio>

#include "cli_checks.h"
#include "commands.h"
#include "edit_source.h"
#include "terralod/format/terrain_edits_json.h"
#include "terralod/materials/terrain_edits.h"

namespace terralod::cli {
namespace {

struct EditArgs {
  std::string tileset, script, source, materials, palette;
  unsigned threads = 0;
  bool rebuildAll = false;
};

// Every stroke touches the data, and paints a material the tileset has.
Status checkStrokes(const std::vector<TerrainEdit>& edits, const TilesetReader& tileset,
                    const std::string& script) {
  const TilesetHeader& h = tileset.header();
  for (size_t i = 0; i < edits.size(); ++i) {
    const TerrainEdit& e = edits[i];
    const std::string where = "edits[" + std::to_string(i) + "]: ";
    if (touchedPoints(e, h.spacingX, h.spacingY, int32_t(h.sourceColumns), int32_t(h.sourceRows)) ==
        0) {
      char text[256];
      std::snprintf(text, sizeof text,
                    "the %s brush at (%g, %g) with radius %g m touches no grid point of the "
                    "terrain (x 0..%g, y 0..%g m)",
                    std::string(brushName(e.brush)).c_str(), e.centerX, e.centerY, e.radius,
                    h.extentMax[0], h.extentMax[1]);
      return makeError(script, where + text);
    }
    if (e.brush != Brush::kPaint) continue;
    bool known = false;
    std::string list;
    for (const TilesetMaterial& m : tileset.metadata().materials) {
      known = known || m.id == e.material;
      list += (list.empty() ? "" : ", ") + std::to_string(m.id) + " " + m.name;
    }
    if (!known)
      return makeError(script, where + "material " + std::to_string(e.material) +
                                   " is not one of the tileset's (" + list + ")");
  }
  return {};
}

// The build options that rebuild the tileset with `edits` added.
Result<BuildOptions> rebuildOptions(const TilesetReader& tileset, const EditArgs& args,
                                    const std::vector<TerrainEdit>& edits) {
  auto options = editSourceOptions(
      tileset, {args.tileset, args.source, args.materials, args.palette, args.threads});
  if (!options) return options;
  options->output = args.tileset;
  if (!args.rebuildAll) options->reuse = args.tileset;  // chunks no stroke reaches are kept
  options->edits.insert(options->edits.end(), edits.begin(), edits.end());
  return options;
}

int runEdit(const EditArgs& args) {
  if (args.tileset.starts_with("http://") || args.tileset.starts_with("https://"))
    return fail(args.tileset + ": edit rewrites a local file, not a URL");
  auto edits = readEditScript(args.script);
  if (!edits) return fail(edits.error().message);
  BuildOptions options;
  {
    auto tileset = TilesetReader::openFile(args.tileset);
    if (!tileset) return fail(tileset.error().message);
    if (Status s = checkStrokes(*edits, **tileset, args.script); !s) return fail(s.error().message);
    auto rebuilt = rebuildOptions(**tileset, args, *edits);
    if (!rebuilt) return fail(rebuilt.error().message);
    options = std::move(*rebuilt);
  }
  TerminalProgress progress;
  auto summary = buildTileset(options, progress, warn);
  if (!summary) return fail(summary.error().message);
  std::printf(
      "terralod: edited %s: %zu stroke(s) applied, %zu recorded in all; rebuilt %llu of %llu "
      "chunks from %s in %.2f s (source read %.2f s, chunks %.2f s)\n",
      args.tileset.c_str(), edits->size(), options.edits.size(),
      (unsigned long long)(summary->chunks - summary->reusedChunks),
      (unsigned long long)summary->chunks, options.input.c_str(), summary->totalSeconds,
      summary->loadSeconds, summary->meshSeconds);
  return 0;
}

}  // namespace

void addEditCommand(CLI::App& root, Runner& run) {
  auto* cmd = root.add_subcommand(
      "edit",
      "Apply brush strokes (raise, lower, smooth, paint) from a script to a VIPM tileset: it is "
      "rebuilt from its source with the strokes applied and recorded, and replaces the old "
      "file only when complete");
  auto args = std::make_shared<EditArgs>();
  cmd->add_option("TILESET", args->tileset, "A VIPM tileset (build --kind vipm), edited in place")
      ->required();
  cmd->add_option("--script", args->script,
                  "EDITS.json: {\"edits\": [{\"brush\": \"raise|lower|smooth|paint\", "
                  "\"center\": [x, y], \"radius\": r, \"amount\": a, \"material\": id}, ...]} "
                  "in metres east and north of the data's south-west sample")
      ->required();
  cmd->add_option("--source", args->source,
                  "The raster the tileset was built from (default: the file its metadata names, "
                  "next to the tileset or in the current directory)");
  cmd->add_option("--materials", args->materials,
                  "The categorical raster it was built with (tilesets built with --materials)")
      ->check(CLI::ExistingFile);
  cmd->add_option("--palette", args->palette, "The --palette it was built with")
      ->check(CLI::ExistingFile);
  cmd->add_option("--threads", args->threads, "Worker threads (default: all cores)")
      ->check(wholeNumber<unsigned>());
  cmd->add_flag("--rebuild-all", args->rebuildAll,
                "Build every chunk again (by default the chunks no new stroke reaches are kept "
                "as they are; the result is the same bytes either way)");
  cmd->footer(
      "Example:\n"
      "  terralod edit dem.tlod --script edits.json --source dem.tif\n"
      "  terralod verify dem.tlod --source dem.tif   # checks it with the edits applied\n"
      "raise/lower: amount metres at the centre, falling smoothly to 0 at the radius; smooth: "
      "amount in (0, 1] toward the 3x3 mean; paint: material id.\n");
  cmd->callback([&run, args] { run = [args] { return runEdit(*args); }; });
}

}  // namespace terralod::cli
