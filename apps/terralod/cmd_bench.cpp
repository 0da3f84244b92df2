// terralod bench TILESET (--flight F.json | --auto-flight) [--source INPUT] --json OUT.json

#include <epoxy/gl.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <nlohmann/json.hpp>

#include "commands.h"
#include "quality_metrics.h"
#include "render_options.h"
#include "terralod/core/atomic_file.h"
#include "terralod/core/parallel.h"
#include "terralod/render/framebuffer.h"
#include "terralod/render/gl_context.h"
#include "terralod/render/terrain_scene.h"
#include "terralod/verify/verifier.h"
#include "texture_metrics.h"

namespace terralod::cli {
namespace {

// Sources up to this many samples per side are measured at every sample; larger ones at every
// k-th sample in x and y, k = ceil(side / this).
constexpr int kExactMetricSide = 4097;

struct BenchCommand {
  RenderOptions options;
  std::string source;
  std::string jsonPath;
};

double percentile(std::vector<double> values, double p) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  const size_t i = size_t(std::ceil(p * double(values.size()))) - (p > 0 ? 1 : 0);
  return values[std::min(i, values.size() - 1)];
}

double millisecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
      .count();
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
  auto created = TerrainScene::create(std::move(tileset).value(), sceneOptions(b.options, false));
  if (!created) return fail(created.error().message);
  TerrainScene& scene = **created;
  auto cameras = camerasFor(b.options, scene.tree());
  if (!cameras) return fail(cameras.error().message);
  if (cameras->empty()) return fail("the flight has no frames");

  std::optional<QualityMetrics> metrics;
  if (source) {
    const int side = std::max(source->columns(), source->rows());
    const int stride = (side + kExactMetricSide - 1) / kExactMetricSide;
    metrics.emplace(scene.tileset(), scene.tree(), *source, stride, hardwareThreads());
  }
  TerrainStyle holeStyle = *style;
  holeStyle.sky = false;

  std::vector<double> selectUs, frameMs, triangles, draws, chunks;
  double maxError = 0.0, maxErrorAll = 0.0, maxPop = 0.0, uploadMsMax = 0.0;
  uint64_t coarserFrames = 0, waitingFrames = 0;
  uint64_t residentMax = 0;
  bool previousComplete = false;
  double imagePopMax = 0.0, imagePopSum = 0.0;
  uint64_t imagePopFrames = 0;
  TexelDensity texels;
  std::vector<SelectedChunk> previousNow;
  std::optional<Framebuffer> popTarget;
  uint64_t holes = 0;
  std::vector<SelectedChunk> previous, current;
  std::optional<Framebuffer> target, lookDown;
  for (size_t i = 0; i < cameras->size(); ++i) {
    auto view = makeView((*cameras)[i]);
    if (!view) return fail("frame " + std::to_string(i) + ": " + view.error().message);
    if (Status s = bindFramebufferOfSize(target, view->camera.width, view->camera.height); !s)
      return fail(s.error().message);
    const auto start = std::chrono::steady_clock::now();
    auto frame = scene.renderFrame(*view, *selection, *style);
    if (!frame) return fail(frame.error().message);
    glFinish();
    frameMs.push_back(millisecondsSince(start));
    selectUs.push_back(frame->selectMicroseconds);
    triangles.push_back(double(frame->draw.triangles));
    draws.push_back(double(frame->draw.drawCalls));
    chunks.push_back(double(frame->selection.selected));
    uploadMsMax = std::max(uploadMsMax, frame->uploadMilliseconds);
    // Resident memory, every frame: GPU copies and decoded chunks waiting for upload.
    residentMax = std::max(residentMax, scene.residency().counters().residentBytes);
    const bool complete = frame->selection.coarserThanWanted == 0;
    coarserFrames += complete ? 0 : 1;
    waitingFrames += frame->waitedOnIo ? 1 : 0;
    // Like the error bound, the texel bound holds where the frame has what it wants.
    if (style->textures && complete)
      addTexelDensity(*view, scene.tree(), scene.store(), scene.selected(), texels);
    if (!metrics) continue;

    current = scene.selected();
    if (i > 0 && selectionsDiffer(previous, current)) {
      // The picture's change from LOD alone: last frame's chunks and this frame's, both
      // morphed for this camera, rendered from it.
      previousNow = previous;
      for (SelectedChunk& c : previousNow)
        c.morph = morphParameter(scene.tree(), *view, *selection, c.node);
      if (Status s = bindFramebufferOfSize(popTarget, view->camera.width, view->camera.height); !s)
        return fail(s.error().message);
      const DrawStats before = scene.drawChunks(*view, previousNow, *style);
      const Image beforeImage = popTarget->readPixels();
      scene.drawChunks(*view, current, *style);
      // (Skipped when last frame's chunks have been evicted since.)
      if (before.missing == 0) {
        const double change = meanAbsoluteDifference(beforeImage, popTarget->readPixels());
        imagePopMax = std::max(imagePopMax, change);
        imagePopSum += change;
        ++imagePopFrames;
      }
    }
    auto error = metrics->maxErrorPixels(*view, current);
    if (!error) return fail(error.error().message);
    // τ holds where the frame has what it wants; frames drawn coarser while chunks stream in
    // are counted apart.
    maxErrorAll = std::max(maxErrorAll, *error);
    if (complete) maxError = std::max(maxError, *error);
    if (i > 0 && complete && previousComplete) {
      auto pop = metrics->maxPopPixels(*view, *selection, previous, current);
      if (!pop) return fail(pop.error().message);
      maxPop = std::max(maxPop, *pop);
    }
    previousComplete = complete;
    std::swap(previous, current);

    auto downView = makeView(lookDownCamera(*view));
    if (!downView) return fail(downView.error().message);
    if (Status s = bindFramebufferOfSize(lookDown, downView->camera.width, downView->camera.height);
        !s)
      return fail(s.error().message);
    scene.renderResident(*downView, *selection, holeStyle);
    holes += metrics->holes(lookDown->readPixels(), *downView, holeStyle.background);
  }

  nlohmann::json j;
  j["tileset"] = b.options.tileset;
  j["gl"] = (*context)->description();
  j["frames"] = cameras->size();
  j["size"] = {(*cameras)[0].width, (*cameras)[0].height};
  j["tau"] = selection->tau;
  j["morph"] = selection->morph;
  j["skirts"] = style->skirts;
  j["select_us_p50"] = percentile(selectUs, 0.5);
  j["select_us_max"] = percentile(selectUs, 1.0);
  j["frame_ms_p50"] = percentile(frameMs, 0.5);
  j["frame_ms_p99"] = percentile(frameMs, 0.99);
  j["frame_ms_max"] = percentile(frameMs, 1.0);
  j["triangles_p50"] = percentile(triangles, 0.5);
  j["triangles_max"] = percentile(triangles, 1.0);
  j["draws_p50"] = percentile(draws, 0.5);
  j["chunks_p50"] = percentile(chunks, 0.5);
  const ResidencyCounters& rc = scene.residency().counters();
  j["loads"] = rc.loads;
  j["evictions"] = rc.evictions;
  j["bytes_read"] = rc.bytesRead;
  j["load_failures"] = rc.failures;
  j["cancelled_requests"] = rc.cancelled;
  j["resident_mb_max"] = double(residentMax) / double(1 << 20);
  j["cache_mb"] = b.options.cacheMB;
  j["frames_waiting_on_io"] = waitingFrames;
  j["coarser_than_wanted_frames"] = coarserFrames;
  j["upload_ms_max"] = uploadMsMax;
  j["textured"] = scene.tileset().header().textured();
  if (texels.any) j["max_texel_per_px"] = texels.max;
  if (texels.anySourceLimited) j["max_texel_per_px_source_limited"] = texels.sourceLimitedMax;
  j["gpu_mb"] = double(scene.gpuBytes()) / 1e6;
  if (metrics) {
    j["source"] = b.source;
    j["metric_stride"] = metrics->stride();
    j["max_error_px"] = maxError;  // over frames with every wanted chunk resident
    j["max_error_px_all"] = maxErrorAll;
    j["max_pop_px"] = maxPop;
    j["holes_total"] = holes;
    // 8-bit units: the largest per-frame mean absolute pixel change from LOD alone, and its
    // average over the frames whose selection changed.
    j["image_pop_mean"] = imagePopMax;
    j["image_pop_mean_avg"] = imagePopFrames ? imagePopSum / double(imagePopFrames) : 0.0;
    j["image_pop_frames"] = imagePopFrames;
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
  if (texels.any) std::printf("; %.2f px per texel max", texels.max);
  if (metrics)
    std::printf("; max error %.3f px, max pop %.3f px, %llu holes, image pop %.3f/255", maxError,
                maxPop, (unsigned long long)holes, imagePopMax);
  std::printf("\nterralod: wrote %s\n", b.jsonPath.c_str());
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
  cmd->add_option("--json", b->jsonPath, "Where to write the figures (JSON)")->required();
  cmd->callback([&run, b] { run = [b] { return runBench(*b); }; });
}

}  // namespace terralod::cli
