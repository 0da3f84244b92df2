#pragma once
// bench's flight: renders every camera headless through the streaming scene, as an application
// would (frames never wait for data), and records each frame's figures. With a source raster it
// also measures the drawn surface against it (error, pops, holes, image pops; on VIPM
// tilesets material pops too, FrameRecord::materialPopPx, which do not read the source).

#include <cmath>
#include <cstdint>
#include <functional>
#include <optional>
#include <vector>

#include <glm/vec3.hpp>

#include "terralod/core/progress.h"
#include "terralod/measure/texture_metrics.h"
#include "terralod/raster/heightfield.h"
#include "terralod/render/image.h"
#include "terralod/render/terrain_scene.h"
#include "terralod/runtime/view.h"

namespace terralod {

/// One frame's figures. Quality figures are NaN where they were not measured: without a
/// source, or when nothing changed (image pops) or there is no last frame (pops).
struct FrameRecord {
  double frameMs = 0;   ///< selection, uploads and drawing, to glFinish
  double selectUs = 0;  ///< selection alone
  double uploadMs = 0;  ///< copying chunks to the GPU
  uint64_t triangles = 0;
  uint64_t vertices = 0;  ///< vertices drawn (DrawStats::vertices)
  uint32_t draws = 0, chunks = 0, uploads = 0, evictions = 0;
  uint32_t culledChunks = 0;     ///< selected but hidden behind nearer terrain: not drawn
  uint64_t culledTriangles = 0;  ///< their triangles (skirts included when drawn)
  bool cullingActive = false;    ///< horizon culling tested chunks (the eye was above the terrain)
  double residentMB = 0;         ///< chunk memory after the frame (GPU copies and decoded chunks)
  double blockSpareMB = 0;       ///< VIPM super-chunk blocks' memory beyond their chunks'
  bool coarser = false;          ///< drew a chunk whose wanted children were not resident, or
                                 ///< a late split still easing in from its parent's surface
  bool easing = false;           ///< drew a late split still easing in (part of `coarser`)
  bool childrenMissing = false;  ///< drew a chunk whose wanted children were not resident
                                 ///< (part of `coarser`): the terrain was still loading
  bool waitedOnIo = false;       ///< blocked on a read
  glm::dvec3 eye{0.0};
  double errorPx = NAN;      ///< largest screen-space error over the source samples in view
  double popPx = NAN;        ///< largest change from selection alone since the last frame
  double morphStepPx = NAN;  ///< VIPM: largest change of the drawn surface since the last frame
  double imagePop = NAN;     ///< mean absolute pixel change from LOD alone (8-bit units)
  bool popComplete = false;  ///< this frame and the last had every wanted chunk (pops count)
  uint64_t holes = 0;        ///< background pixels in the look-down render
  /// VIPM tilesets: pixels whose material (the largest splat weight's; no terrain counts as
  /// one) differs between the last frame's LOD state, geomorphed for this frame, and this
  /// one's, both drawn from this frame's camera. Measured with a source, where `popComplete`
  /// holds.
  double materialPopPx = NAN;
  /// The same with the last frame's state as it was drawn (its own geomorph).
  double materialMorphStepPx = NAN;
  double fanMs = NAN;        ///< VIPM with --stitch fans: the frame's fan stitching (render thread)
  uint32_t blots = 0;        ///< VIPM chunks drawn as blots
  uint32_t superChunks = 0;  ///< VIPM super-chunk calls (each a block's blots)
  /// VIPM, with a source: mean absolute pixel change (8-bit units) between the picture and the
  /// same chunks with no blot (their materials faded), i.e. every blot switching at once.
  double blotSwitch = NAN;
  // With vegetation (bench --vegetation; the caller's afterFrame fills them).
  double vegetationMs = NAN;        ///< the software LDI warp (all threads, wall)
  double compositeMs = NAN;         ///< uploading its picture and compositing it
  uint64_t splats = 0;              ///< splats drawn
  uint32_t ldiTiles = 0;            ///< tiles drawn as LDIs
  double vegetationResidentMB = 0;  ///< decoded LDIs and corner heights
  /// With --vegetation-reference, on the frames it measures: SSIM of the frame against the
  /// same frame with the vegetation ray traced, and the share of pixels where one shows a
  /// plant and the other not.
  /// Vegetation: mean absolute pixel change (8-bit units) from the tiles' choices of LDIs
  /// alone: this frame drawn with the last frame's choices against its own (NaN where no
  /// tile chose differently).
  double vegetationPop = NAN;
  double vegetationSsim = NAN;
  double vegetationCoverageError = NAN;
};

/// Whether the flight starts from the roots alone or with the first view loaded.
enum class BenchStart : uint8_t {
  kCold,  ///< the first frames draw what has arrived, as a viewer just opened
  kWarm   ///< the first camera's chunks load first (not a frame): steady streaming from there
};

struct BenchFlightOptions {
  BenchStart start = BenchStart::kCold;
  SelectionOptions selection;
  TerrainStyle style;
  const Heightfield* source = nullptr;  ///< measure quality against it (optional)
  int metricStride = 0;   ///< measure every k-th source sample in x and y; 0: automatic
  size_t keepFrames = 0;  ///< keep this many evenly spaced frames' images (contact sheet)
  /// Called before each frame with its index (bench --edit-script: strokes during the
  /// flight); a failure ends the flight with it. Empty: nothing.
  std::function<Status(size_t frame, TerrainScene& scene)> beforeFrame;
  /// Called after each frame is drawn and timed, before its quality figures, to add the
  /// figures of what the caller drew into the frame (a composited layer's), which it may
  /// measure by drawing the view again. Empty: nothing.
  std::function<Status(size_t frame, const View& view, TerrainScene& scene, FrameRecord& record)>
      afterFrame;
};

struct BenchFlightResult {
  std::vector<FrameRecord> frames;
  double warmStartMs = NAN;           ///< BenchStart::kWarm: loading the first view (not a frame)
  TexelDensity texels;                ///< over frames that had every wanted chunk resident
  int metricStride = 0;               ///< every how many source samples the quality figures used
  std::vector<double> reconstructMs;  ///< per VIPM chunk decoded: decode and reconstruction, ms
  std::vector<double> fanChangeMs;    ///< per VIPM chunk whose fans changed: their making, ms
  std::vector<Image> keptImages;
  std::vector<size_t> keptFrameIndices;
};

/// Flies `cameras` over `scene`. Progress is one step per frame. Fails only on GL or decoding
/// errors (a frame naming its index).
Result<BenchFlightResult> flyBench(TerrainScene& scene, const std::vector<Camera>& cameras,
                                   const BenchFlightOptions& options, Progress& progress);

/// The p-quantile (0..1) of `values` by the nearest-rank method; 0 for none. NaNs are skipped.
double percentile(std::vector<double> values, double p);

}  // namespace terralod
