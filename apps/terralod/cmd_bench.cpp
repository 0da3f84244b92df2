// terralod bench TILESET (--flight F.json | --auto-flight) [--source INPUT] --json OUT.json
//                [--report DIR]

#include <algorithm>
#include <cstdio>
#include <nlohmann/json.hpp>

#include "bench_flight.h"
#include "bench_report.h"
#include "cli_checks.h"
#include "commands.h"
#include "render_options.h"
#include "terralod/core/atomic_file.h"
#include "terralod/render/gl_context.h"
#include "terralod/render/terrain_scene.h"
#include "terralod/verify/verifier.h"

namespace terralod::cli {
namespace {

struct BenchCommand {
  RenderOptions options;
  std::string source;
  std::string jsonPath;
  std::string reportDir;
  int metricStride = 0;
};

template <typename Field>
std::vector<double> column(const std::vector<FrameRecord>& frames, Field field) {
  std::vector<double> out;
  out.reserve(frames.size());
  for (const FrameRecord& r : frames) out.push_back(double(field(r)));
  return out;
}

// The flight's figures, bench's JSON.
nlohmann::json summarize(const BenchCommand& b, const TerrainScene& scene,
                         const BenchFlightResult& flight, const GlContext& context,
                         const SelectionOptions& selection, const TerrainStyle& style) {
  const std::vector<FrameRecord>& f = flight.frames;
  nlohmann::json j;
  j["tileset"] = b.options.tileset;
  j["gl"] = context.description();
  j["frames"] = f.size();
  j["tau"] = selection.tau;
  j["morph"] = selection.morph;
  j["skirts"] = style.skirts;
  const auto selectUs = column(f, [](const FrameRecord& r) { return r.selectUs; });
  const auto frameMs = column(f, [](const FrameRecord& r) { return r.frameMs; });
  const auto triangles = column(f, [](const FrameRecord& r) { return r.triangles; });
  j["select_us_p50"] = percentile(selectUs, 0.5);
  j["select_us_max"] = percentile(selectUs, 1.0);
  j["frame_ms_p50"] = percentile(frameMs, 0.5);
  j["frame_ms_p99"] = percentile(frameMs, 0.99);
  j["frame_ms_max"] = percentile(frameMs, 1.0);
  j["triangles_p50"] = percentile(triangles, 0.5);
  j["triangles_max"] = percentile(triangles, 1.0);
  j["draws_p50"] = percentile(column(f, [](const FrameRecord& r) { return r.draws; }), 0.5);
  j["chunks_p50"] = percentile(column(f, [](const FrameRecord& r) { return r.chunks; }), 0.5);
  // Horizon culling: selected chunks (and their triangles) hidden behind nearer terrain.
  j["horizon_culling"] = b.options.horizonCulling == HorizonCulling::kOn;
  const auto culled = column(f, [](const FrameRecord& r) { return r.culledChunks; });
  const auto culledTriangles = column(f, [](const FrameRecord& r) { return r.culledTriangles; });
  j["culled_chunks_p50"] = percentile(culled, 0.5);
  j["culled_chunks_max"] = percentile(culled, 1.0);
  j["culled_triangles_p50"] = percentile(culledTriangles, 0.5);
  j["culled_triangles_max"] = percentile(culledTriangles, 1.0);
  const ResidencyCounters& rc = scene.residency().counters();
  j["loads"] = rc.loads;
  j["evictions"] = rc.evictions;
  j["bytes_read"] = rc.bytesRead;
  j["load_failures"] = rc.failures;
  j["cancelled_requests"] = rc.cancelled;
  j["resident_mb_max"] =
      percentile(column(f, [](const FrameRecord& r) { return r.residentMB; }), 1.0);
  j["cache_mb"] = b.options.cacheMB;
  uint64_t waiting = 0, coarser = 0, easing = 0, holes = 0, imagePopFrames = 0;
  double maxError = 0, maxErrorAll = 0, maxPop = 0, uploadMax = 0, imagePopMax = 0,
         imagePopMaxAll = 0, imagePopSum = 0;
  for (const FrameRecord& r : f) {
    waiting += r.waitedOnIo ? 1 : 0;
    coarser += r.coarser ? 1 : 0;
    easing += r.easing ? 1 : 0;
    holes += r.holes;
    uploadMax = std::max(uploadMax, r.uploadMs);
    if (!std::isnan(r.errorPx)) {
      // τ holds where the frame has what it wants; frames drawn coarser while chunks stream
      // in are counted apart.
      maxErrorAll = std::max(maxErrorAll, r.errorPx);
      if (!r.coarser) maxError = std::max(maxError, r.errorPx);
    }
    if (!std::isnan(r.popPx)) maxPop = std::max(maxPop, r.popPx);
    if (!std::isnan(r.imagePop)) {
      imagePopMaxAll = std::max(imagePopMaxAll, r.imagePop);
      if (r.popComplete) {
        imagePopMax = std::max(imagePopMax, r.imagePop);
        imagePopSum += r.imagePop;
        ++imagePopFrames;
      }
    }
  }
  j["frames_waiting_on_io"] = waiting;
  j["coarser_than_wanted_frames"] = coarser;
  j["easing_frames"] = easing;  // (among them) frames with a late split easing in
  j["upload_ms_max"] = uploadMax;
  j["textured"] = scene.tileset().header().textured();
  if (flight.texels.any) j["max_texel_per_px"] = flight.texels.max;
  if (flight.texels.anySourceLimited)
    j["max_texel_per_px_source_limited"] = flight.texels.sourceLimitedMax;
  j["gpu_mb"] = double(scene.gpuBytes()) / 1e6;
  if (!b.source.empty()) {
    j["source"] = b.source;
    j["metric_stride"] = flight.metricStride;
    j["max_error_px"] = maxError;  // over frames with every wanted chunk resident
    j["max_error_px_all"] = maxErrorAll;
    j["max_pop_px"] = maxPop;
    j["holes_total"] = holes;
    // 8-bit units: the largest per-frame mean absolute pixel change from LOD alone, and its
    // average over the frames whose selection changed (both between frames that had what they
    // wanted, like max_pop_px; _all also over frames while chunks streamed in).
    j["image_pop_mean"] = imagePopMax;
    j["image_pop_mean_all"] = imagePopMaxAll;
    j["image_pop_mean_avg"] = imagePopFrames ? imagePopSum / double(imagePopFrames) : 0.0;
    j["image_pop_frames"] = imagePopFrames;
  }
  return j;
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
  auto context = GlContext::createHeadless();
  if (!context) return fail(context.error().message);
  // Streaming, as an application would run: frames never wait for data.
  auto created =
      TerrainScene::create(std::move(tileset).value(), sceneOptions(b.options, false, **context));
  if (!created) return fail(created.error().message);
  TerrainScene& scene = **created;
  auto cameras = camerasFor(b.options, scene.tree());
  if (!cameras) return fail(cameras.error().message);
  if (cameras->empty()) return fail("the flight has no frames");

  BenchFlightOptions flightOptions;
  flightOptions.selection = *selection;
  flightOptions.style = *style;
  flightOptions.source = source ? &*source : nullptr;
  flightOptions.metricStride = b.metricStride;
  flightOptions.keepFrames = b.reportDir.empty() ? 0 : kReportSheetFrames;
  TerminalProgress progress;
  auto flight = flyBench(scene, *cameras, flightOptions, progress);
  if (!flight) return fail(flight.error().message);

  nlohmann::json j = summarize(b, scene, *flight, **context, *selection, *style);
  j["size"] = {(*cameras)[0].width, (*cameras)[0].height};
  if (!b.reportDir.empty())
    if (Status s = writeBenchReport(b.reportDir, *flight, j, commandLine()); !s)
      return fail(s.error().message);
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
