#include "terralod/measure/bench_flight.h"

#include <epoxy/gl.h>

#include <algorithm>
#include <chrono>

#include "terralod/core/parallel.h"
#include "terralod/measure/quality_metrics.h"
#include "terralod/measure/vipm_quality.h"
#include "terralod/render/framebuffer.h"

namespace terralod {
namespace {

// Sources up to this many samples per side are measured at every sample; larger ones at every
// k-th sample in x and y, k = ceil(side / this).
constexpr int kExactMetricSide = 4097;

double millisecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
      .count();
}

// The frames whose images go on the contact sheet: `count` evenly spaced, first and last kept.
std::vector<size_t> evenlySpaced(size_t frames, size_t count) {
  std::vector<size_t> out;
  if (count == 0 || frames == 0) return out;
  if (count >= frames) count = frames;
  for (size_t k = 0; k < count; ++k) out.push_back(count == 1 ? 0 : k * (frames - 1) / (count - 1));
  return out;
}

// The quality figures of one frame against the source, and the state they carry between
// frames (the last selection, whether it was complete).
class QualityPass {
 public:
  QualityPass(TerrainScene& scene, const Heightfield& source, const BenchFlightOptions& options)
      : mScene(scene), mOptions(options) {
    const int side = std::max(source.columns(), source.rows());
    const int stride = options.metricStride > 0 ? options.metricStride
                                                : (side + kExactMetricSide - 1) / kExactMetricSide;
    mMetrics.emplace(scene.tileset(), scene.tree(), source, stride, hardwareThreads());
    // VIPM chunks are measured as the VIPM kind draws them (holes alike for both kinds).
    if (scene.tileset().header().meshKind == MeshKind::kVipm)
      mVipm.emplace(scene.tileset(), scene.tree(), source, stride, hardwareThreads(),
                    options.selection.morph ? Geomorph::kOn : Geomorph::kOff,
                    options.style.skirts ? options.style.stitch : VipmStitch::kFlanges);
    mHoleStyle = options.style;
    mHoleStyle.sky = false;
  }

  int stride() const { return mMetrics->stride(); }

  Status measure(size_t i, const View& view, FrameRecord& r) {
    const SelectionOptions& selection = mOptions.selection;
    mCurrent = mScene.selected();
    if (i > 0 && selectionsDiffer(mPrevious, mCurrent)) {
      // The picture's change from LOD alone: last frame's chunks and this frame's, both
      // morphed for this camera, rendered from it.
      mPreviousNow = mPrevious;
      for (SelectedChunk& c : mPreviousNow)
        c.morph = morphParameter(mScene.tree(), view, selection, c.node);
      if (Status s = bindFramebufferOfSize(mPopTarget, view.camera.width, view.camera.height); !s)
        return s;
      const DrawStats before = mScene.drawChunks(view, mPreviousNow, mOptions.style);
      const Image beforeImage = mPopTarget->readPixels();
      mScene.drawChunks(view, mCurrent, mOptions.style);
      // (Skipped when last frame's chunks have been evicted since.)
      if (before.missing == 0)
        r.imagePop = meanAbsoluteDifference(beforeImage, mPopTarget->readPixels());
    }
    if (mVipm && mOptions.style.blots == VipmBlots::kOn) {
      // The blot switch: this frame's picture against the same chunks with the blots drawn
      // one pass per material (faded to their averages), as if every blot switched at once.
      if (Status s = bindFramebufferOfSize(mPopTarget, view.camera.width, view.camera.height); !s)
        return s;
      const DrawStats drawn = mScene.drawChunks(view, mCurrent, mOptions.style, selection);
      if (drawn.blots > 0 && drawn.missing == 0) {
        const Image withBlots = mPopTarget->readPixels();
        TerrainStyle faded = mOptions.style;
        faded.blots = VipmBlots::kFadeOnly;
        mScene.drawChunks(view, mCurrent, faded, selection);
        r.blotSwitch = meanAbsoluteDifference(withBlots, mPopTarget->readPixels());
      }
    }
    if (mVipm) mCurrentDrawn = VipmQuality::drawn(mScene.tree(), view, selection.tau, mCurrent);
    auto error = mVipm ? mVipm->maxErrorPixels(view, mCurrentDrawn)
                       : mMetrics->maxErrorPixels(view, mCurrent);
    if (!error) return error.error();
    r.errorPx = *error;
    // Pops count between two frames that both had what they wanted; frames drawn coarser
    // while chunks stream in hand over differently (reported apart).
    r.popComplete = i > 0 && !r.coarser && mPreviousComplete;
    if (r.popComplete && mVipm) {
      // Last frame's VIPM states geomorphed for this camera (the pop), and as drawn (the step).
      const auto previousNow =
          VipmQuality::geomorphedFor(mScene.tree(), view, selection, mPrevious, mPreviousDrawn);
      auto pop = mVipm->maxPopPixels(view, previousNow, mCurrentDrawn);
      if (!pop) return pop.error();
      r.popPx = *pop;
      auto step = mVipm->maxPopPixels(view, mPreviousDrawn, mCurrentDrawn);
      if (!step) return step.error();
      r.morphStepPx = *step;
      if (Status s = materialPops(view, previousNow, r); !s) return s;
    } else if (r.popComplete) {
      auto pop = mMetrics->maxPopPixels(view, selection, mPrevious, mCurrent);
      if (!pop) return pop.error();
      r.popPx = *pop;
    }
    mPreviousComplete = !r.coarser;
    std::swap(mPrevious, mCurrent);
    std::swap(mPreviousDrawn, mCurrentDrawn);

    auto downView = makeView(lookDownCamera(view));
    if (!downView) return downView.error();
    if (Status s =
            bindFramebufferOfSize(mLookDown, downView->camera.width, downView->camera.height);
        !s)
      return s;
    mScene.renderResident(*downView, selection, mHoleStyle);
    r.holes = mMetrics->holes(mLookDown->readPixels(), *downView, mHoleStyle.background);
    return {};
  }

 private:
  // Material pops on VIPM tilesets, as material-ID images (TerrainScene::drawVipmMaterials)
  // from this frame's camera: the pixels whose material differs between this frame's state
  // and the last frame's, the latter geomorphed for this frame (`previousNow`, as for
  // max_pop_px: the pop) and as it was drawn (the morph step).
  Status materialPops(const View& view, std::span<const VipmQuality::Drawn> previousNow,
                      FrameRecord& r) {
    if (Status s = bindFramebufferOfSize(mMaterialTarget, view.camera.width, view.camera.height);
        !s)
      return s;
    auto draw = [&](std::span<const VipmChunkAt> chunks, Image& image) {
      const DrawStats stats =
          mScene.drawVipmMaterials(view, chunks, mOptions.style, mOptions.selection);
      image = mMaterialTarget->readPixels();
      return stats.missing == 0;
    };
    // (Skipped when last frame's chunks have been evicted since.)
    if (draw(previousNow, mMaterialPop) && draw(mPreviousDrawn, mMaterialStep) &&
        draw(mCurrentDrawn, mMaterialNow)) {
      r.materialPopPx = double(changedMaterials(mMaterialPop, mMaterialNow));
      r.materialMorphStepPx = double(changedMaterials(mMaterialStep, mMaterialNow));
    }
    return {};
  }

  static uint64_t changedMaterials(const Image& a, const Image& b) {
    uint64_t changed = 0;
    for (size_t k = 0; k < a.rgba.size(); k += 4)
      changed += vipmMaterialOfPixel(a.rgba[k]) != vipmMaterialOfPixel(b.rgba[k]);
    return changed;
  }

  TerrainScene& mScene;
  const BenchFlightOptions& mOptions;
  std::optional<QualityMetrics> mMetrics;
  std::optional<VipmQuality> mVipm;
  std::vector<VipmQuality::Drawn> mPreviousDrawn, mCurrentDrawn;  // VIPM: each chunk's θ
  TerrainStyle mHoleStyle;
  std::vector<SelectedChunk> mPrevious, mCurrent, mPreviousNow;
  bool mPreviousComplete = false;
  std::optional<Framebuffer> mPopTarget, mLookDown, mMaterialTarget;
  Image mMaterialPop, mMaterialStep, mMaterialNow;
};

}  // namespace

double percentile(std::vector<double> values, double p) {
  std::erase_if(values, [](double v) { return std::isnan(v); });
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  const size_t i = size_t(std::ceil(p * double(values.size()))) - (p > 0 ? 1 : 0);
  return values[std::min(i, values.size() - 1)];
}

Result<BenchFlightResult> flyBench(TerrainScene& scene, const std::vector<Camera>& cameras,
                                   const BenchFlightOptions& options, Progress& progress) {
  BenchFlightResult result;
  result.frames.reserve(cameras.size());
  result.keptFrameIndices = evenlySpaced(cameras.size(), options.keepFrames);
  std::optional<QualityPass> quality;
  if (options.source) {
    quality.emplace(scene, *options.source, options);
    result.metricStride = quality->stride();
  }
  auto frameError = [](size_t i, const Error& e) {
    return Error{"frame " + std::to_string(i) + ": " + e.message};
  };

  if (options.start == BenchStart::kWarm && !cameras.empty()) {
    auto view = makeView(cameras.front());
    if (!view) return frameError(0, view.error());
    const auto start = std::chrono::steady_clock::now();
    scene.preload(*view, options.selection);
    result.warmStartMs = millisecondsSince(start);
  }

  std::optional<Framebuffer> target;
  size_t nextKept = 0;
  progress.begin("flying", cameras.size());
  for (size_t i = 0; i < cameras.size(); ++i) {
    if (options.beforeFrame)
      if (Status s = options.beforeFrame(i, scene); !s) return frameError(i, s.error());
    auto view = makeView(cameras[i]);
    if (!view) return frameError(i, view.error());
    if (Status s = bindFramebufferOfSize(target, view->camera.width, view->camera.height); !s)
      return s.error();
    const auto start = std::chrono::steady_clock::now();
    auto frame = scene.renderFrame(*view, options.selection, options.style);
    if (!frame) return frameError(i, frame.error());
    glFinish();
    FrameRecord r;
    r.frameMs = millisecondsSince(start);
    r.selectUs = frame->selectMicroseconds;
    r.uploadMs = frame->uploadMilliseconds;
    r.triangles = frame->draw.triangles;
    r.vertices = frame->draw.vertices;
    result.reconstructMs.insert(result.reconstructMs.end(), frame->reconstructMs.begin(),
                                frame->reconstructMs.end());
    result.fanChangeMs.insert(result.fanChangeMs.end(), frame->fanChangeMs.begin(),
                              frame->fanChangeMs.end());
    r.fanMs = frame->fanFrameMs;
    r.draws = frame->draw.drawCalls;
    r.blots = frame->draw.blots;
    r.superChunks = frame->draw.superChunks;
    r.chunks = frame->selection.selected;
    r.culledChunks = frame->horizon.culled;
    r.cullingActive = frame->horizon.active;
    r.culledTriangles =
        frame->horizon.triangles + (options.style.skirts ? frame->horizon.skirtTriangles : 0);
    r.uploads = frame->uploads;
    r.evictions = frame->evictions;
    // Resident memory, every frame: GPU copies and decoded chunks waiting for upload.
    r.residentMB = double(scene.residency().counters().residentBytes) / double(1 << 20);
    r.blockSpareMB = double(scene.vipmBlockSpareBytes()) / double(1 << 20);
    // A late split easing in is drawn above its morph schedule, i.e. coarser than wanted too.
    r.easing = frame->easing != 0;
    r.childrenMissing = frame->selection.coarserThanWanted != 0;
    r.coarser = r.childrenMissing || r.easing;
    r.waitedOnIo = frame->waitedOnIo;
    r.eye = view->camera.eye;
    if (nextKept < result.keptFrameIndices.size() && result.keptFrameIndices[nextKept] == i) {
      result.keptImages.push_back(target->readPixels());
      ++nextKept;
    }
    // Like the error bound, the texel bound holds where the frame has what it wants.
    if (options.style.textures && !r.coarser)
      addTexelDensity(*view, scene.tree(), scene.store(), scene.selected(), result.texels);
    if (options.afterFrame)
      if (Status s = options.afterFrame(i, *view, scene, r); !s) return frameError(i, s.error());
    if (quality)
      if (Status s = quality->measure(i, *view, r); !s) return frameError(i, s.error());
    result.frames.push_back(r);
    progress.advance();
  }
  progress.end();
  return result;
}

}  // namespace terralod
