#pragma once
// A tileset ready to draw: GL glue over the runtime's FrameDriver (which holds the streaming
// policy: uploads within a budget, selection among the resident chunks, late-split easing,
// requests, eviction, dispatch), with a loader pool, the chunks on the GPU (GpuChunkStore)
// and the renderer, registered as the static RTIN chunk kind and, for tilesets that have them,
// the VIPM chunk kind (vipm_chunk_kind.h). One call per frame. What
// `render`, `bench` and the viewer share. Render thread only.
//
// A frame never waits for IO unless `complete` is set (single images, golden tests): then it
// first waits until what it wants is resident or has failed. Only the roots are read before
// the first frame. A tileset using a mesh kind with no registered kind is refused.

#include <chrono>
#include <functional>
#include <limits>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "terralod/format/tileset_reader.h"
#include "terralod/render/gl_context.h"
#include "terralod/render/gl_worker.h"
#include "terralod/render/gpu_chunk_store.h"
#include "terralod/render/static_chunk_kind.h"
#include "terralod/render/terrain_renderer.h"
#include "terralod/render/vipm_chunk_kind.h"
#include "terralod/runtime/chunk_tree.h"
#include "terralod/runtime/frame_clock.h"
#include "terralod/runtime/frame_driver.h"
#include "terralod/runtime/horizon_culling.h"
#include "terralod/runtime/residency.h"
#include "terralod/runtime/selection.h"
#include "terralod/runtime/task_runner.h"

namespace terralod {

struct SceneOptions {
  uint64_t cacheBytes = uint64_t{512} << 20;  ///< --cache-mb: GPU copies plus decoded chunks
  unsigned loaderThreads = 2;
  /// Loads started and not yet collected (FrameDriverOptions::maxInFlight). Loads are started
  /// once a frame, so this is also about how many can arrive per frame: enough to keep the
  /// loader threads busy through a slow frame.
  unsigned loadsInFlight = 32;
  double uploadMillisecondsPerFrame = 4.0;  ///< GPU uploads per frame (at least one chunk)
  bool complete = false;  ///< every frame waits until its wanted chunks are resident
  std::function<void(const std::string&)> log;  ///< one line per chunk that fails to load
  /// The context the scene draws with. When set, GPU memory for chunks is made ahead of need
  /// on a second context sharing it, on a worker thread, so that no frame waits for a driver
  /// to allocate and clear it (GlWorker); without it, memory is made when needed.
  GlContext* context = nullptr;
  /// Leave out the selected chunks nearer terrain hides (horizon_culling.h; never with skirts
  /// off, whose cracks a hidden chunk could show through).
  HorizonCulling horizonCulling = HorizonCulling::kOn;
};

struct FrameStats {
  SelectionStats selection;
  DrawStats draw;
  double selectMicroseconds = 0;
  double uploadMilliseconds = 0;  ///< copying to the GPU this frame
  uint32_t uploads = 0;           ///< chunks brought to the GPU this frame
  uint32_t deferredUploads = 0;   ///< chunks left for a later frame: their GPU memory is on its way
  uint32_t evictions = 0;         ///< chunks freed this frame
  bool waitedOnIo = false;        ///< this frame blocked on a read (only with `complete`)
  /// Chunks drawn above their morph schedule: late splits easing in from the parent's surface
  /// (their error bound is then the parent's, over τ). A frame with any is, like one with
  /// `selection.coarserThanWanted`, still catching up with what it wants.
  uint32_t easing = 0;
  HorizonCullingStats horizon;  ///< selected chunks not drawn: hidden behind nearer terrain
  /// VIPM chunks decoded since the last frame: each one's decode and reconstruction time on
  /// its loader thread, milliseconds.
  std::vector<double> reconstructMs;
  /// VIPM fan stitching (--stitch fans) on the render thread this frame, milliseconds: each
  /// chunk whose fans changed (its level or a neighbour's, or a border vertex geomorphing),
  /// and the whole frame's stitching (gathering the border points included); NaN without.
  std::vector<double> fanChangeMs;
  double fanFrameMs = std::numeric_limits<double>::quiet_NaN();
};

class TerrainScene {
 public:
  /// Takes the opened tileset and reads its roots. A GlContext must be current.
  static Result<std::unique_ptr<TerrainScene>> create(std::unique_ptr<TilesetReader> tileset,
                                                      SceneOptions options = {});
  ~TerrainScene();

  /// One frame for `view` into the bound framebuffer. With `reselect` false the last frame's
  /// selection and morph parameters are drawn again from the new view (the viewer's "freeze
  /// selection"). Fails only when a root cannot be drawn.
  Result<FrameStats> renderFrame(const View& view, const SelectionOptions& selection,
                                 const TerrainStyle& style, bool reselect = true);

  /// Loads what `view` wants and waits until it is resident or has failed, drawing nothing:
  /// a streaming viewer's first view behind a loading screen (bench --warm-start).
  void preload(const View& view, const SelectionOptions& selection) {
    mDriver->update(view, selection, FrameCompleteness::kComplete);
  }

  /// Selects among the resident chunks for `view` and draws them, without loading or asking
  /// for anything (a second view of the same moment, e.g. bench's look-down hole check).
  FrameStats renderResident(const View& view, const SelectionOptions& selection,
                            const TerrainStyle& style);

  /// Draws the given chunks (with their morph parameters) from `view`; chunks not on the GPU
  /// are skipped (counted in DrawStats::missing): for comparing two selections from a camera.
  /// `selection`: the τ and morphing VIPM chunks pick their levels with.
  DrawStats drawChunks(const View& view, std::span<const SelectedChunk> chunks,
                       const TerrainStyle& style, const SelectionOptions& selection = {});

  /// VIPM tilesets: draws `chunks`, each at its own allowed error (geomorphed as `selection`
  /// says), from `view` into the bound framebuffer as a material-ID image
  /// (VipmChunkKind::addMaterialIdDraws; skirts as `style` says, nothing else of it): for
  /// comparing the materials two frames showed from one camera. Chunks not on the GPU are
  /// skipped (DrawStats::missing); on a tileset without VIPM chunks every chunk is missing.
  DrawStats drawVipmMaterials(const View& view, std::span<const VipmChunkAt> chunks,
                              const TerrainStyle& style, const SelectionOptions& selection);

  const ChunkTree& tree() const { return mTree; }
  const GpuChunkStore& store() const { return mStore; }
  const TilesetReader& tileset() const { return *mTileset; }
  const Residency& residency() const { return mDriver->residency(); }
  /// An edit's new nodes (VipmChunkSet::apply) and the tileset's level errors now: the tree
  /// takes their boxes at once, and the driver swaps their chunks in over the next frames
  /// (FrameDriver::replaceNodes).
  void replaceNodes(std::vector<NodeReplacement> nodes, std::span<const double> levelErrors);
  /// Replaced nodes whose new chunks are not drawn yet.
  size_t pendingReplacements() const { return mDriver->pendingReplacements(); }
  /// The chunks the last frame selected.
  const std::vector<SelectedChunk>& selected() const { return mDriver->selected(); }
  uint64_t gpuBytes() const {
    return mStore.residentBytes() + (mVipmKind ? mVipmKind->gpuBytes() : 0);
  }
  /// VIPM tilesets: GPU memory the super-chunk blocks hold beyond their chunks' own (spare
  /// vertex room, unused texture layers), which the chunk budget does not count.
  uint64_t vipmBlockSpareBytes() const { return mVipmKind ? mVipmKind->blockSpareBytes() : 0; }
  /// Memory the resident chunks' occluder grids hold (horizon culling).
  uint64_t occluderBytes() const { return mDriver->occluderBytes(); }
  /// The renderer, for adding composited layers (TerrainRenderer::addLayer).
  TerrainRenderer& renderer() { return mRenderer; }

 private:
  TerrainScene(std::unique_ptr<TilesetReader> tileset, ChunkTree tree, TerrainRenderer renderer,
               SceneOptions options);
  // One frame of `chunks`: the renderer begins it (clear, sky), each kind adds its opaque
  // draws, the renderer finishes it (composited layers, overlays).
  DrawStats drawSelection(const View& view, std::span<const SelectedChunk> chunks,
                          const TerrainStyle& style, const SelectionOptions& selection);
  // The chunks of `selected` to draw: without those horizon culling finds hidden.
  std::span<const SelectedChunk> visibleChunks(const View& view,
                                               std::span<const SelectedChunk> selected,
                                               const TerrainStyle& style, FrameStats& stats);

  std::unique_ptr<TilesetReader> mTileset;
  ChunkTree mTree;
  SceneOptions mOptions;
  GpuChunkStore mStore;
  TerrainRenderer mRenderer;
  StaticChunkKind mStaticKind;
  std::unique_ptr<VipmChunkKind> mVipmKind;  // when the tileset has VIPM chunks
  // The registered kinds that draw into the frame, in registration order (drawSelection).
  std::vector<DrawnChunkKind<TerrainFrame>*> mDrawnKinds;
  // Stops (after finishing its job) before the store, which deletes what it left unadopted.
  std::unique_ptr<GlWorker> mGlWorker;
  std::unique_ptr<ThreadPool> mPool;
  SteadyFrameClock mClock;
  std::unique_ptr<FrameDriver> mDriver;  // reset first: waits for the loads on mPool
  std::vector<SelectedChunk> mOtherView;
  KindRuns mRuns;
  std::vector<SelectedChunk> mVisible;
};

}  // namespace terralod
