// terralod bench TILESET (--flight F.json | --auto-flight) [--source INPUT] --json OUT.json
//                [--report DIR]

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>

#include "bench_editor.h"
#include "cli_checks.h"
#include "commands.h"
#include "edit_source.h"
#include "render_options.h"
#include "scene_vegetation.h"
#include "terralod/build/vipm_builder.h"
#include "terralod/core/atomic_file.h"
#include "terralod/measure/bench_report.h"
#include "terralod/measure/bench_summary.h"
#include "terralod/render/gl_context.h"
#include "terralod/render/terrain_scene.h"
#include "terralod/verify/verifier.h"
#include "vegetation_reference.h"

namespace terralod::cli {
namespace {

struct BenchCommand {
  RenderOptions options;
  std::string source;
  std::string editScript, editSource;
  size_t editEvery = 60;
  std::string jsonPath;
  std::string reportDir;
  int metricStride = 0;
  bool warmStart = false;
  int referenceEvery = 10;  ///< --reference-every: frames between ray-traced comparisons
};

// The editor of bench --edit-script: the tileset's chunk set (its source read again, every
// chunk kept from the tileset) and the script's strokes.
Result<std::unique_ptr<BenchEditor>> benchEditor(const BenchCommand& b,
                                                 const TilesetReader& tileset) {
  if (!b.source.empty())
    return Error{
        "--edit-script and --source exclude each other (the metrics would count the "
        "strokes as error); the edit's source is --edit-source"};
  auto strokes = readEditScript(b.editScript);
  if (!strokes) return strokes.error();
  auto set = openTilesetChunkSet(tileset, b.options.tileset, b.editSource);
  if (!set) return set.error();
  return std::make_unique<BenchEditor>(std::move(*set), std::move(*strokes), b.editEvery);
}

int runBench(const BenchCommand& b) {
  if (b.options.flightFile.empty() && !b.options.autoFlight)
    return fail("bench needs a flight: --flight F.json or --auto-flight");
  auto selection = selectionOptions(b.options);
  if (!selection) return fail(selection.error().message);
  auto style = terrainStyle(b.options);
  if (!style) return fail(style.error().message);
  auto output = AtomicFile::create(b.jsonPath);
  if (!output) return fail(output.error().message);
  if (!b.reportDir.empty())
    if (Status s = checkReportTarget(b.reportDir); !s) return fail(s.error().message);

  auto tileset = TilesetReader::openPathOrUrl(b.options.tileset);  // a path or an http(s):// URL
  if (!tileset) return fail(tileset.error().message);
  std::optional<Heightfield> source;
  if (!b.source.empty()) {
    auto loaded = loadTilesetSource(**tileset, b.source);
    if (!loaded) return fail(loaded.error().message);
    source = std::move(loaded).value();
  }
  std::unique_ptr<BenchEditor> editor;
  if (!b.editScript.empty()) {
    auto made = benchEditor(b, **tileset);
    if (!made) return fail(made.error().message);
    editor = std::move(*made);
  }
  auto context = GlContext::createHeadless();
  if (!context) return fail(context.error().message);
  // Streaming, as an application would run: frames never wait for data.
  auto created =
      TerrainScene::create(std::move(tileset).value(), sceneOptions(b.options, false, **context));
  if (!created) return fail(created.error().message);
  TerrainScene& scene = **created;
  style->stitch = stitchFor(b.options, scene.tileset().header());
  auto vegetation = addSceneVegetation(b.options, scene);
  if (!vegetation) return fail(vegetation.error().message);
  auto cameras = camerasFor(b.options, scene.tree());
  if (!cameras) return fail(cameras.error().message);
  if (cameras->empty()) return fail("the flight has no frames");

  BenchFlightOptions flightOptions;
  flightOptions.start = b.warmStart ? BenchStart::kWarm : BenchStart::kCold;
  flightOptions.selection = *selection;
  flightOptions.style = *style;
  flightOptions.source = source ? &*source : nullptr;
  flightOptions.metricStride = b.metricStride;
  flightOptions.keepFrames = b.reportDir.empty() ? 0 : kReportSheetFrames;
  if (editor)
    flightOptions.beforeFrame = [&editor](size_t frame, TerrainScene& s) {
      return editor->beforeFrame(frame, s);
    };
  if (b.options.vegetationReference && !vegetation->painter)
    return fail("--vegetation-reference needs --vegetation V.tlv");
  std::unique_ptr<VegetationReference> reference;
  if (b.options.vegetationReference) {
    reference = std::make_unique<VegetationReference>(*vegetation, scene);
    if (!b.reportDir.empty()) reference->keepPictures();
  }
  std::optional<Framebuffer> popTarget;
  if (vegetation->painter)
    flightOptions.afterFrame = [&, every = size_t(b.referenceEvery), due = size_t(0)](
                                   size_t i, const View& view, TerrainScene& s,
                                   FrameRecord& r) mutable {
      const veg::VegetationFrameStats& v = vegetation->painter->lastFrame();
      r.vegetationMs = v.warp.warpMs;
      r.compositeMs = vegetation->layer->times().compositeMs +
                      (vegetation->far ? vegetation->far->lastMs() : 0.0);
      r.splats = v.warp.splats;
      r.ldiTiles = v.warp.tiles;
      r.vegetationResidentMB = double(v.residentBytes) / double(1 << 20);
      auto pop = vegetationPop(*vegetation, s, view, *style, *selection, popTarget);
      if (!pop) return Status{pop.error()};
      r.vegetationPop = *pop;
      // Against the truth every k-th frame, or the first after it whose terrain is loaded:
      // the traced plants stand on the finest heights, and a coarser stand-in drawn while its
      // children load can bury them where the drawn textures lie on top of it.
      if (!reference || i < due || r.childrenMissing) return Status{};
      due = i + every;
      return reference->measure(view, s, *style, *selection, r);
    };
  BenchRunInfo info;
  info.tileset = b.options.tileset;
  info.gl = (*context)->description();
  info.source = b.source;
  info.cacheMB = b.options.cacheMB;
  info.horizonCulling = b.options.horizonCulling == HorizonCulling::kOn;
  TerminalProgress progress;
  auto run = runBenchFlight(scene, *cameras, flightOptions, info, progress);
  if (!run) return fail(run.error().message);
  const BenchFlightResult* flight = &run->flight;
  nlohmann::json& j = run->summary;
  j["warm_start_ms"] =
      std::isnan(flight->warmStartMs) ? nlohmann::json() : nlohmann::json(flight->warmStartMs);
  if (editor) editor->addFigures(j);
  if (!b.reportDir.empty()) {
    if (Status s = writeBenchReport(b.reportDir, *flight, j, commandLine()); !s)
      return fail(s.error().message);
    if (reference)
      if (Status s = reference->writePictures(b.reportDir); !s) return fail(s.error().message);
  }
  const std::string text = j.dump(2) + "\n";
  if (Status s = output->write(text); !s) return fail(s.error().message);
  if (Status s = output->commit(); !s) return fail(s.error().message);
  std::printf(
      "terralod: %zu frames at tau %.2f: frame p50 %.2f ms, p99 %.2f ms; select p50 %.1f us; "
      "%.0f triangles p50, %.0f draws p50",
      cameras->size(), selection->tau, j["frame_ms_p50"].get<double>(),
      j["frame_ms_p99"].get<double>(), j["select_us_p50"].get<double>(),
      j["triangles_p50"].get<double>(), j["draws_p50"].get<double>());
  if (flight->texels.any) std::printf("; %.2f px per texel max", flight->texels.max);
  if (source)
    std::printf("; max error %.3f px, max pop %.3f px, %llu holes, image pop %.3f/255",
                j["max_error_px"].get<double>(), j["max_pop_px"].get<double>(),
                (unsigned long long)j["holes_total"].get<uint64_t>(),
                j["image_pop_mean"].get<double>());
  if (editor)
    std::printf("; %llu strokes swapped in, latency p50 %.0f ms (%.0f frames), max %.0f ms",
                (unsigned long long)j["edit_swapped"].get<uint64_t>(),
                j["edit_latency_ms_p50"].get<double>(), j["edit_latency_frames_p50"].get<double>(),
                j["edit_latency_ms_max"].get<double>());
  if (j.contains("vegetation_ms_p50"))
    std::printf("; vegetation warp p50 %.1f ms, composite p50 %.1f ms, %.0f LDI tiles p50",
                j["vegetation_ms_p50"].get<double>(), j["composite_ms_p50"].get<double>(),
                j["ldi_tiles_p50"].get<double>());
  if (j.contains("vegetation_pop_mean"))
    std::printf(", vegetation pop %.3f/255", j["vegetation_pop_mean"].get<double>());
  if (j.contains("vegetation_ssim_mean"))
    std::printf("; vegetation SSIM mean %.3f (min %.3f), coverage error %.2f%%",
                j["vegetation_ssim_mean"].get<double>(), j["vegetation_ssim_min"].get<double>(),
                100.0 * j["vegetation_coverage_error"].get<double>());
  if (j.contains("material_pop_px"))
    std::printf("; material pop %.0f px", j["material_pop_px"].get<double>());
  std::printf("\nterralod: wrote %s\n", b.jsonPath.c_str());
  if (!b.reportDir.empty()) std::printf("terralod: wrote %s/report.md\n", b.reportDir.c_str());
  return 0;
}

}  // namespace

void addBenchCommand(CLI::App& root, Runner& run) {
  auto* cmd = root.add_subcommand(
      "bench",
      "Fly a tileset headless and measure it: selection and frame times, triangles, draw calls "
      "and, against the source raster, screen-space error, pops and holes");
  auto b = std::make_shared<BenchCommand>();
  addRenderOptions(*cmd, b->options, false);
  cmd->add_option("--source", b->source,
                  "The raster the tileset was built from: measure max_error_px, max_pop_px and "
                  "holes_total against it");
  cmd->add_option("--metric-stride", b->metricStride,
                  "With --source: measure every k-th sample in x and y (default: every sample up "
                  "to 4097 a side, ceil(side / 4097) above)")
      ->check(wholeNumber<int>(1));
  cmd->add_option("--edit-script", b->editScript,
                  "VIPM tilesets: apply the strokes of this edit script (terralod edit) during "
                  "the flight, one every --edit-every frames, regenerating on a worker thread and "
                  "swapping the chunks in while drawing; reports edit_latency_ms (stroke to "
                  "its chunks drawn)");
  cmd->add_option("--edit-every", b->editEvery, "Frames between strokes (default 60)")
      ->check(wholeNumber<size_t>(1));
  cmd->add_option("--edit-source", b->editSource,
                  "The raster the tileset was built from, for --edit-script (default: the file "
                  "its metadata names, next to it or in the current directory)");
  cmd->add_flag("--warm-start", b->warmStart,
                "Load the first camera's chunks before the first frame (as behind a viewer's "
                "loading screen; its time is warm_start_ms), so the flight measures streaming "
                "from a settled view rather than from the roots alone");
  cmd->add_option("--reference-every", b->referenceEvery,
                  "With --vegetation-reference: compare every k-th frame (the first included; "
                  "or the first after it whose terrain is all loaded) with its ray-traced truth "
                  "(default 10)")
      ->check(wholeNumber<int>(1));
  cmd->add_option("--json", b->jsonPath, "Where to write the figures (JSON)")->required();
  cmd->add_option("--report", b->reportDir,
                  "Also write a report to this directory: report.md with the figures, plots of "
                  "frame time, selection time, triangles, resident memory and error over the "
                  "flight (PNG, drawn by gnuplot), frames.csv and a contact sheet");
  cmd->footer(
      "Examples:\n"
      "  terralod bench dem.tlod --auto-flight --source dem.tif --json bench.json --report "
      "report/\n"
      "  terralod bench http://host/dem.tlod --flight flight.json --cache-mb 256 --json "
      "bench.json\n"
      "Flight files: {\"fov_deg\": 60, \"size\": [1024, 768], \"frames\": 300,\n"
      "               \"keyframes\": [{\"eye\": [x, y, z], \"target\": [x, y, z]}, ...]}\n");
  cmd->callback([&run, b] { run = [b] { return runBench(*b); }; });
}

}  // namespace terralod::cli
