#include "terralod/measure/bench_summary.h"

#include <algorithm>
#include <cmath>

namespace terralod {
namespace {

template <typename Field>
std::vector<double> column(const std::vector<FrameRecord>& frames, Field field) {
  std::vector<double> out;
  out.reserve(frames.size());
  for (const FrameRecord& r : frames) out.push_back(double(field(r)));
  return out;
}

}  // namespace

nlohmann::json summarizeBench(const TerrainScene& scene, const BenchFlightResult& flight,
                              const BenchFlightOptions& options, const BenchRunInfo& info) {
  const SelectionOptions& selection = options.selection;
  const TerrainStyle& style = options.style;
  const std::vector<FrameRecord>& f = flight.frames;
  nlohmann::json j;
  j["tileset"] = info.tileset;
  j["gl"] = info.gl;
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
  j["vertices_p50"] = percentile(column(f, [](const FrameRecord& r) { return r.vertices; }), 0.5);
  if (!f.empty() && !std::isnan(f.front().vegetationMs)) {
    // Vegetation: the software warp, the composite, splats, LDI tiles and their memory.
    const auto warp = column(f, [](const FrameRecord& r) { return r.vegetationMs; });
    j["vegetation_ms_p50"] = percentile(warp, 0.5);
    j["vegetation_ms_p99"] = percentile(warp, 0.99);
    j["composite_ms_p50"] =
        percentile(column(f, [](const FrameRecord& r) { return r.compositeMs; }), 0.5);
    j["splats_p50"] = percentile(column(f, [](const FrameRecord& r) { return r.splats; }), 0.5);
    j["ldi_tiles_p50"] =
        percentile(column(f, [](const FrameRecord& r) { return r.ldiTiles; }), 0.5);
    j["vegetation_resident_mb"] =
        percentile(column(f, [](const FrameRecord& r) { return r.vegetationResidentMB; }), 1.0);
    // Pops from the LDI choices alone, as image_pop_mean counts the terrain's: the largest
    // per-frame mean, and the mean over the frames that chose differently.
    const auto pops = column(f, [](const FrameRecord& r) { return r.vegetationPop; });
    double popSum = 0;
    size_t popFrames = 0;
    for (double p : pops)
      if (!std::isnan(p)) {
        popSum += p;
        ++popFrames;
      }
    j["vegetation_pop_mean"] = percentile(pops, 1.0);
    j["vegetation_pop_mean_avg"] = popFrames ? popSum / double(popFrames) : 0.0;
    j["vegetation_pop_frames"] = popFrames;
    const auto ssim = column(f, [](const FrameRecord& r) { return r.vegetationSsim; });
    const auto coverage = column(f, [](const FrameRecord& r) { return r.vegetationCoverageError; });
    size_t measured = 0;
    double ssimSum = 0, coverageSum = 0;
    for (size_t k = 0; k < ssim.size(); ++k)
      if (!std::isnan(ssim[k])) {
        ++measured;
        ssimSum += ssim[k];
        coverageSum += coverage[k];
      }
    if (measured > 0) {
      j["vegetation_reference_frames"] = measured;
      j["vegetation_ssim_mean"] = ssimSum / double(measured);
      j["vegetation_ssim_min"] = percentile(ssim, 0.0);
      j["vegetation_coverage_error"] = coverageSum / double(measured);
      j["vegetation_coverage_error_max"] = percentile(coverage, 1.0);
    }
  }
  // VIPM tilesets: each chunk's decode and reconstruction on its loader thread.
  if (scene.tileset().header().meshKind == MeshKind::kVipm) {
    j["reconstruct_ms_p50"] = percentile(flight.reconstructMs, 0.5);
    j["reconstruct_ms_max"] = percentile(flight.reconstructMs, 1.0);
    // Fan stitching (--stitch fans): per chunk whose fans changed, and per frame.
    j["stitch"] = style.stitch == VipmStitch::kFans ? "fans" : "flanges";
    j["blots"] = style.blots == VipmBlots::kOn;
    j["blots_p50"] =
        percentile(column(f, [](const FrameRecord& r) { return double(r.blots); }), 0.5);
    j["super_chunks"] = style.superChunks == VipmSuperChunks::kOn;
    j["super_chunk_calls_p50"] =
        percentile(column(f, [](const FrameRecord& r) { return double(r.superChunks); }), 0.5);
    // Memory the budget does not count (docs/architecture.md "Super-chunks").
    j["block_spare_mb_max"] =
        percentile(column(f, [](const FrameRecord& r) { return r.blockSpareMB; }), 1.0);
    if (options.source && style.blots == VipmBlots::kOn) {
      j["blot_switch_mean_max"] =
          percentile(column(f, [](const FrameRecord& r) { return r.blotSwitch; }), 1.0);
      j["blot_switch_mean_p50"] =
          percentile(column(f, [](const FrameRecord& r) { return r.blotSwitch; }), 0.5);
    }
    if (style.stitch == VipmStitch::kFans && style.skirts) {
      const auto fanFrame = column(f, [](const FrameRecord& r) { return r.fanMs; });
      j["fan_changes"] = flight.fanChangeMs.size();
      j["fan_change_ms_p50"] = percentile(flight.fanChangeMs, 0.5);
      j["fan_change_ms_p99"] = percentile(flight.fanChangeMs, 0.99);
      j["fan_change_ms_max"] = percentile(flight.fanChangeMs, 1.0);
      j["fan_frame_ms_p50"] = percentile(fanFrame, 0.5);
      j["fan_frame_ms_max"] = percentile(fanFrame, 1.0);
    }
  }
  // Quality figures (with --source) on VIPM tilesets: pixels whose material changed from the
  // LOD state alone between two frames that had what they wanted (both drawn from the later
  // camera, last frame's state geomorphed for it, as max_pop_px): the most, the 99th
  // percentile and the mean over those frames.
  if (options.source && scene.tileset().header().meshKind == MeshKind::kVipm) {
    std::vector<double> materialPops;
    double materialStep = 0.0;
    for (const FrameRecord& r : f) {
      if (!std::isnan(r.materialPopPx)) materialPops.push_back(r.materialPopPx);
      if (!std::isnan(r.materialMorphStepPx))
        materialStep = std::max(materialStep, r.materialMorphStepPx);
    }
    double sum = 0.0;
    for (double v : materialPops) sum += v;
    j["material_pop_px"] = percentile(materialPops, 1.0);
    j["material_pop_px_p99"] = percentile(materialPops, 0.99);
    j["material_pop_px_mean"] = materialPops.empty() ? 0.0 : sum / double(materialPops.size());
    j["material_pop_frames"] = materialPops.size();
    // The same with last frame's state as drawn: everything that changed material, the
    // geomorph's steady motion included.
    j["material_morph_step_px"] = materialStep;
  }
  j["draws_p50"] = percentile(column(f, [](const FrameRecord& r) { return r.draws; }), 0.5);
  j["chunks_p50"] = percentile(column(f, [](const FrameRecord& r) { return r.chunks; }), 0.5);
  // Horizon culling: selected chunks (and their triangles) hidden behind nearer terrain.
  j["horizon_culling"] = info.horizonCulling;
  const auto culled = column(f, [](const FrameRecord& r) { return r.culledChunks; });
  const auto culledTriangles = column(f, [](const FrameRecord& r) { return r.culledTriangles; });
  j["culling_active_frames"] =
      std::count_if(f.begin(), f.end(), [](const FrameRecord& r) { return r.cullingActive; });
  j["culled_chunks_p50"] = percentile(culled, 0.5);
  j["culled_chunks_max"] = percentile(culled, 1.0);
  j["culled_triangles_p50"] = percentile(culledTriangles, 0.5);
  j["culled_triangles_max"] = percentile(culledTriangles, 1.0);
  j["occluder_grids_mb"] = double(scene.occluderBytes()) / 1e6;  // after the flight
  const ResidencyCounters& rc = scene.residency().counters();
  j["loads"] = rc.loads;
  j["evictions"] = rc.evictions;
  j["bytes_read"] = rc.bytesRead;
  j["load_failures"] = rc.failures;
  j["cancelled_requests"] = rc.cancelled;
  j["resident_mb_max"] =
      percentile(column(f, [](const FrameRecord& r) { return r.residentMB; }), 1.0);
  j["cache_mb"] = info.cacheMB;
  uint64_t waiting = 0, coarser = 0, easing = 0, holes = 0, imagePopFrames = 0;
  double maxError = 0, maxErrorAll = 0, maxPop = 0, maxMorphStep = 0, uploadMax = 0,
         imagePopMax = 0, imagePopMaxAll = 0, imagePopSum = 0;
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
    if (!std::isnan(r.morphStepPx)) maxMorphStep = std::max(maxMorphStep, r.morphStepPx);
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
  if (options.source) {
    j["source"] = info.source;
    j["metric_stride"] = flight.metricStride;
    j["max_error_px"] = maxError;  // over frames with every wanted chunk resident
    j["max_error_px_all"] = maxErrorAll;
    j["max_pop_px"] = maxPop;
    // VIPM: everything that moved between consecutive pictures, the geomorph's steady motion
    // included (max_pop_px leaves that out, as on static tilesets).
    if (scene.tileset().header().meshKind == MeshKind::kVipm) j["max_morph_step_px"] = maxMorphStep;
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

Result<BenchRun> runBenchFlight(TerrainScene& scene, const std::vector<Camera>& cameras,
                                const BenchFlightOptions& options, const BenchRunInfo& info,
                                Progress& progress) {
  if (cameras.empty()) return Error{"the flight has no frames"};
  auto flight = flyBench(scene, cameras, options, progress);
  if (!flight) return flight.error();
  BenchRun run;
  run.flight = std::move(flight).value();
  run.summary = summarizeBench(scene, run.flight, options, info);
  run.summary["size"] = {cameras[0].width, cameras[0].height};
  return run;
}

}  // namespace terralod
