#pragma once
// The streaming policy of a frame, without GL: what the render thread does once per frame
// before drawing. It owns the residency of a tileset's chunks and the late-split easing, and
// drives the chunk kinds (chunk_kind.h) registered for the tileset's mesh kinds:
//
//   update(view):
//     1. collect finished loads; prepare + upload the ready ones, most wanted first, within
//        the per-frame upload budget (measured on the injected clock; at least one chunk)
//     2. select among the resident chunks (selectChunks with Residency::drawable)
//     3. late-split easing: children split off a parent drawn last frame start at its
//        surface (t = 1) and ease to their schedule over 16 frames
//     4. touch the drawn chunks and their ancestors; request the children of chunks drawn
//        coarser than wanted (priority τ/ρ, nearest first), then of chunks within a factor 2
//        of splitting (prefetch, priority + 1)
//     5. evict the least recently used chunks over the budget (each kind releases its own,
//        the driver the chunk's occluder grid)
//     6. dispatch the most wanted loads on the injected TaskRunner (read + decode there)
//   With FrameCompleteness::kComplete, update repeats 1-6 (uploads unlimited), sleeping on
//   the clock between rounds, until nothing the frame wants is on its way.
//
// The upload budget of step 1 is uploadMillisecondsPerFrame or uploadFrameShare of the last
// frame's interval (from one update to the next), whichever is more: a slow frame (software
// rendering, a huge view) does not starve the stream that would make the next ones right.
//
// Render thread only (loads run on the runner). Deterministic for a deterministic runner and
// clock: the same flight gives the same selections, loads and evictions.

#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <span>
#include <string>
#include <unordered_map>
#include <vector>

#include "terralod/core/result.h"
#include "terralod/format/tileset_reader.h"
#include "terralod/runtime/chunk_kind.h"
#include "terralod/runtime/chunk_tree.h"
#include "terralod/runtime/frame_clock.h"
#include "terralod/runtime/horizon_culling.h"
#include "terralod/runtime/residency.h"
#include "terralod/runtime/selection.h"
#include "terralod/runtime/task_runner.h"
#include "terralod/runtime/view.h"

namespace terralod {

/// Whether a frame may show chunks coarser than wanted while the rest load.
enum class FrameCompleteness : uint8_t {
  kStreaming,  ///< never wait for IO: draw what is resident, ask for the rest
  kComplete    ///< wait until what the frame wants is resident or has failed (single images)
};

struct FrameDriverOptions {
  uint64_t cacheBytes = uint64_t{512} << 20;  ///< resident plus decoded-not-uploaded
  unsigned maxInFlight = 4;                   ///< loads running at once
  double uploadMillisecondsPerFrame = 4.0;    ///< at least one chunk per frame
  /// With longer frames: this share of the last frame's interval, when that is more.
  double uploadFrameShare = 0.1;
  FrameCompleteness completeness = FrameCompleteness::kStreaming;
  std::function<void(const std::string&)> log;  ///< one line per chunk that fails to load
};

/// What update() did.
struct UpdateStats {
  SelectionStats selection;
  double selectMicroseconds = 0;
  double uploadMilliseconds = 0;
  uint32_t uploads = 0;          ///< chunks uploaded this frame
  uint32_t deferredUploads = 0;  ///< ready chunks left for later: their memory is on its way
  uint32_t evictions = 0;        ///< chunks released this frame
  bool waitedOnIo = false;       ///< the frame slept waiting for loads (complete frames)
  uint32_t easing = 0;           ///< chunks drawn above their morph schedule (late splits)
};

/// What an edit changed of a node.
enum class ReplacedPart : uint8_t {
  kBytes,   ///< its bytes (and record): drawn chunks are decoded again
  kRecord,  ///< only its record (e.g. a flange depth): a drawn chunk takes it in place
};

/// A node's new bytes and record (an edit: VipmChunkSet::apply).
struct NodeReplacement {
  uint32_t node = 0;
  NodeRecord record;
  NodeBytes bytes;  ///< the node's bytes now (for loads to come), changed or not
  ReplacedPart part = ReplacedPart::kBytes;
};

class FrameDriver {
 public:
  /// Checks that every node's mesh kind is registered, then loads and uploads the roots on
  /// the calling thread. `tileset`, `tree`, the kinds, `runner` and `clock` must outlive the
  /// driver; `tree` must be the tileset's.
  static Result<std::unique_ptr<FrameDriver>> create(const TilesetReader& tileset,
                                                     const ChunkTree& tree, ChunkKinds kinds,
                                                     TaskRunner& runner, FrameClock& clock,
                                                     FrameDriverOptions options);
  ~FrameDriver();  ///< waits for loads still running
  FrameDriver(const FrameDriver&) = delete;
  FrameDriver& operator=(const FrameDriver&) = delete;

  /// One frame's update for `view` (see above); selected() then holds what to draw.
  UpdateStats update(const View& view, const SelectionOptions& selection) {
    return update(view, selection, mOptions.completeness);
  }
  /// The same with this frame's completeness (e.g. a streaming viewer's first view loaded
  /// complete, as behind a loading screen).
  UpdateStats update(const View& view, const SelectionOptions& selection,
                     FrameCompleteness completeness);

  /// Nodes whose bytes and records changed (an edit): later loads read these, and resident
  /// ones are decoded again on the loader threads and swapped in by a later update (the old
  /// ones are drawn until then: no frame waits for them); a resident one whose record alone
  /// changed (ReplacedPart::kRecord) takes it in place if its kind can
  /// (ChunkKind::updateRecord). The tree's boxes are the caller's (ChunkTree::updateNode).
  void replaceNodes(std::vector<NodeReplacement> nodes);
  /// Replaced nodes whose new bytes are not drawn yet (resident, loading or waiting).
  size_t pendingReplacements() const { return mResidency->stale(); }

  /// The chunks the last update selected, with their (eased) morph parameters.
  const std::vector<SelectedChunk>& selected() const { return mSelected; }
  const SelectionStats& lastSelection() const { return mLastSelection; }
  const Residency& residency() const { return *mResidency; }
  const ChunkKinds& kinds() const { return mKinds; }

  /// Horizon culling (horizon_culling.h): writes to `visible` the chunks of `chunks` (a
  /// selection among the resident chunks for `view`, e.g. selected()) that nearer drawn
  /// terrain does not hide, in their order. `nearPlane`: the renderer's near-plane distance
  /// in metres. Selection, loads and morphs do not change; only fewer chunks are drawn.
  /// The resident chunks' occluder grids (those their kinds made on decode) are the
  /// occluders.
  HorizonCullingStats cullHidden(const View& view, std::span<const SelectedChunk> chunks,
                                 double nearPlane, std::vector<SelectedChunk>& visible);
  /// Memory the resident chunks' occluder grids hold (counted in the cache budget too).
  uint64_t occluderBytes() const { return mOccluderBytes; }

 private:
  // Whether a step may upload beyond the per-frame budget.
  enum class UploadLimit : uint8_t { kBudget, kUnlimited };

  FrameDriver(const TilesetReader& tileset, const ChunkTree& tree, ChunkKinds kinds,
              TaskRunner& runner, FrameClock& clock, FrameDriverOptions options);
  Status loadRoots();
  void step(const View& view, const SelectionOptions& selection, FrameCompleteness completeness,
            UploadLimit limit, UpdateStats& stats);
  void uploadReady(UploadLimit limit, UpdateStats& stats);
  // Tells the residency what the kinds hold besides their chunks (after uploads and releases).
  void noteSharedBytes();
  void easeLateSplits(const SelectionOptions& selection, FrameCompleteness completeness,
                      UpdateStats& stats);
  void requestWanted(const View& view, const SelectionOptions& selection);
  ChunkKind& kindOf(uint32_t node);

  const TilesetReader& mTileset;
  const ChunkTree& mTree;
  ChunkKinds mKinds;
  FrameClock& mClock;
  FrameDriverOptions mOptions;
  std::unique_ptr<Residency> mResidency;  // after mKinds: its loads use them
  std::vector<SelectedChunk> mSelected;
  SelectionStats mLastSelection;
  // Late splits: a chunk whose children arrived after its split distance hands over to them
  // at the parent's surface (t = 1), easing to their scheduled morph over a few frames.
  std::vector<uint64_t> mDrawnFrame;
  std::vector<uint64_t> mAncestorFrame;  // per node: the mFrame requestWanted last walked it
  std::vector<float> mEntryMorph;
  uint64_t mFrame = 2;
  double mUploadBudget = 0.0;      // this frame's, milliseconds
  double mLastUpdateStart = -1.0;  // clock milliseconds; < 0 before the first update
  HorizonCuller mCuller;
  std::vector<OccluderGrid> mOccluders;  // per node, while resident
  // Replaced nodes (read on loader threads).
  struct Replacements {
    std::mutex mutex;
    std::unordered_map<uint32_t, std::shared_ptr<const NodeReplacement>> nodes;
  };
  std::shared_ptr<Replacements> mReplacements = std::make_shared<Replacements>();
  uint64_t mOccluderBytes = 0;
  void keepOccluders(uint32_t node, OccluderGrid grid);
};

}  // namespace terralod
