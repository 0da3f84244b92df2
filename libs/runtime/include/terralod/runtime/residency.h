#pragma once
// Which chunks are in memory, under a byte budget (Ulrich §15; the VIPM paper's streaming).
// The render thread drives it once per frame; loads (IO and decoding) run on a TaskRunner.
//
// Every node has an explicit state:
//
//   absent ──request──► queued ──dispatch──► loading ──done──► ready ──markResident──► resident
//     ▲  ◄──not requested again (cancelled)──┘          │                                  │
//     │                                                 └──error──► failed ──retry frame──►│ absent
//     └──────────────────────────── evict (least recently used first) ◄────────────────────┘
//
// The budget holds what is resident or ready, what the kinds hold besides their chunks (shared
// memory, e.g. VIPM super-chunk blocks' spare room), and what the loads in flight will bring:
// each load reserves the largest chunk of its level seen so far, with the shared memory its
// upload added (before the first, of the nearest level above), until its upload, so loads
// start only while that fits. A chunk that is drawn, an ancestor of one, or
// wanted (requested) is in use and never evicted: when what a view wants does not fit, the frames
// draw coarser instead of loading and evicting the same chunks over and over.
//
// The resident set is closed under parents: a chunk is requested only when its parent is
// resident, and only chunks without resident (or loading) children are evicted. Selection can
// therefore always walk from the roots to what it draws, and a chunk whose children are
// missing is drawn itself: never a hole, never a wait. Roots are loaded before the first frame
// and never evicted.
//
// Kind-independent: what a load produces is an opaque ChunkPayload (the renderer's decoded
// chunk of whatever mesh kind) with its byte size.

#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <span>
#include <string>
#include <vector>

#include "terralod/core/result.h"
#include "terralod/runtime/chunk_tree.h"
#include "terralod/runtime/occluder_grid.h"
#include "terralod/runtime/task_runner.h"

namespace terralod {

struct ChunkPayload {
  virtual ~ChunkPayload() = default;
};

struct LoadedChunk {
  std::unique_ptr<ChunkPayload> payload;
  uint64_t bytes = 0;      ///< memory it holds until uploaded
  uint64_t bytesRead = 0;  ///< from the source
  /// Horizon culling's occluders under its surface (empty: the kind makes none). The frame
  /// driver keeps it while the chunk is resident and adds its bytes to `bytes`.
  OccluderGrid occluders;
};

/// Reads and decodes one chunk. Called on loader threads: must be thread-safe.
using ChunkLoadFunction = std::function<Result<LoadedChunk>(uint32_t node)>;

enum class ChunkState : uint8_t { kAbsent, kQueued, kLoading, kReady, kResident, kFailed };

struct ResidencyOptions {
  uint64_t budgetBytes = uint64_t{512} << 20;  ///< resident (GPU) plus decoded-not-uploaded
  unsigned maxInFlight = 4;                    ///< loads running at once
  /// Decoded chunks waiting for their upload at most: no load starts while this many wait
  /// (a backlog would hold chunks decoded for an older view in line ahead of what is wanted
  /// now, an edit's new bytes too).
  unsigned maxReady = 8;
  uint32_t retryFrames = 30;  ///< first retry of a failed chunk; doubles
};

struct ResidencyCounters {
  uint64_t loads = 0;          ///< chunks loaded
  uint64_t evictions = 0;      ///< resident chunks evicted
  uint64_t bytesRead = 0;      ///< from the source
  uint64_t failures = 0;       ///< loads that failed (each retried later)
  uint64_t cancelled = 0;      ///< queued requests dropped because nobody wanted them any more
  uint64_t discarded = 0;      ///< loaded chunks dropped unused (budget)
  uint64_t residentBytes = 0;  ///< now: resident plus ready plus shared
  uint64_t sharedBytes = 0;    ///< now: what the kinds hold besides their chunks (setSharedBytes)
  uint64_t residentBytesMax = 0;
};

/// A chunk decoded and waiting for its upload.
struct ReadyChunk {
  uint32_t node = 0;
  LoadedChunk chunk;
  /// A resident chunk decoded again (invalidate): upload it in place of the one drawn, then
  /// markRefreshed.
  bool refresh = false;
};

class Residency {
 public:
  /// `log` receives one line per chunk that fails (the first time it fails).
  Residency(const ChunkTree& tree, ChunkLoadFunction load, TaskRunner& runner,
            ResidencyOptions options, std::function<void(const std::string&)> log = {});
  ~Residency();  ///< waits for loads still running
  Residency(const Residency&) = delete;
  Residency& operator=(const Residency&) = delete;

  /// Loads a chunk on the calling thread (the roots, before the first frame).
  Result<LoadedChunk> loadNow(uint32_t node);

  /// Per node, 1 when resident (SelectionOptions::drawable).
  std::span<const uint8_t> drawable() const { return mDrawable; }
  ChunkState state(uint32_t node) const { return mNodes[node].state; }

  // --- once per frame, on the render thread, in this order ---
  /// Collects finished loads; returns those now ready, most wanted first.
  std::vector<ReadyChunk> collect();
  /// The caller put a ready chunk on the GPU, taking `gpuBytes`, and dropped its payload;
  /// the kind's shared memory grew by `sharedGrowth` with it (counted now, and in what later
  /// loads of its level reserve).
  void markResident(const ReadyChunk& chunk, uint64_t gpuBytes, uint64_t sharedGrowth = 0);
  /// The same for a chunk from loadNow().
  void markLoadedNow(uint32_t node, uint64_t gpuBytes);
  /// What the kinds hold now besides their chunks (ChunkKind::sharedBytes): counted in the
  /// budget with them.
  void setSharedBytes(uint64_t bytes);
  /// A refreshed chunk was uploaded in place of the old one, now holding `gpuBytes`.
  void markRefreshed(const ReadyChunk& chunk, uint64_t gpuBytes);
  /// The node's bytes changed (an edit): a resident chunk is decoded again on a loader thread
  /// and comes back from collect() as a refresh (it stays drawn meanwhile); one loading or
  /// waiting for its upload is decoded again once resident; an absent one simply loads the
  /// new bytes when wanted.
  void invalidate(uint32_t node);
  /// Nodes invalidated whose new bytes are not uploaded yet (resident, loading or ready).
  size_t stale() const;
  /// Whether `node` is one of those.
  bool stale(uint32_t node) const;
  /// Gives a ready chunk back unused (e.g. the frame's upload budget ran out): kept for later.
  void returnReady(ReadyChunk chunk);
  /// `node` is in use this frame (drawn, an ancestor of a drawn chunk, or a child of one).
  void touch(uint32_t node);
  /// `node` is wanted: lower priority values load first. Needs a resident parent. A resident
  /// one is in use this frame.
  void request(uint32_t node, float priority);
  /// Least recently used chunks to free to get under budget (not used this frame); the caller
  /// frees them and they become absent.
  std::vector<uint32_t> evict();
  /// Drops requests not renewed this frame and starts the most wanted loads; ends the frame.
  void dispatch();

  const ResidencyCounters& counters() const { return mCounters; }
  uint64_t frame() const { return mFrame; }
  size_t inFlight() const { return mInFlight; }
  size_t queued() const { return mQueue.size(); }
  /// Loaded chunks waiting to be uploaded (collected and returned, or not collected yet).
  size_t readyWaiting() const { return mReady.size(); }

 private:
  struct Node {
    ChunkState state = ChunkState::kAbsent;
    float priority = 0;
    uint64_t lastUsed = 0, requested = 0, retryAt = 0;
    uint32_t failures = 0;
    uint64_t gpuBytes = 0;
    uint32_t busyChildren = 0;  // children loading, ready or resident
    bool stale = false;         // invalidated: its drawn or coming payload has old bytes
    bool refreshing = false;    // a refresh load is running or waiting for its upload
  };
  struct Finished {
    uint32_t node;
    Result<LoadedChunk> result;
    bool refresh = false;
  };
  void post(uint32_t node, bool refresh);
  void startRefreshes();
  // ResidencyOptions::maxReady decoded chunks wait for an upload: no load starts meanwhile.
  bool uploadsBehind() const { return mReady.size() >= mOptions.maxReady; }
  void adjustParent(uint32_t node, int delta);
  void addBytes(int64_t delta);
  // What a load of `node` reserves: all of it until it is collected, then what its upload may
  // add beyond its decoded bytes until it is uploaded or dropped.
  uint64_t reserve(uint32_t node) const;
  // Drops what `node` reserves.
  void unreserve(uint32_t node);
  void noteChunkBytes(uint32_t node, uint64_t bytes);
  bool fits(uint32_t node) const;

  const ChunkTree& mTree;
  ChunkLoadFunction mLoad;
  TaskRunner& mRunner;
  ResidencyOptions mOptions;
  std::function<void(const std::string&)> mLog;
  std::vector<Node> mNodes;
  std::vector<uint8_t> mDrawable;
  std::vector<uint64_t> mLevelLargest;  // per level: the largest chunk seen (bytes)
  uint64_t mLargest = 0;                // of any level
  uint64_t mReserved = 0;               // by the loads in flight
  std::vector<uint64_t> mReservedBy;    // per node: its load's reservation
  std::vector<uint32_t> mQueue;         // queued nodes
  std::vector<uint32_t> mResident;      // resident nodes (for eviction)
  std::vector<ReadyChunk> mReady;       // loaded, not yet uploaded
  std::vector<uint32_t> mStale;         // invalidated nodes not settled yet
  uint64_t mFrame = 1;
  size_t mInFlight = 0;
  ResidencyCounters mCounters;

  std::shared_ptr<std::mutex> mDoneMutex;
  std::shared_ptr<std::vector<Finished>> mDone;
  std::shared_ptr<size_t> mRunning;  // tasks not finished (guarded by mDoneMutex)
};

}  // namespace terralod
