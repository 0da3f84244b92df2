#pragma once
// Brush strokes on a drawn VIPM tileset (the `view` brush, bench --edit-script): a stroke is
// applied to the tileset's chunk set on a worker thread (VipmChunkSet::apply). The chunks it
// reaches come first as their whole grids (interim: exact, made in milliseconds), which poll()
// hands to the scene at once; once their progressive meshes are made, poll() hands those, and
// the scene swaps each in over the next frames: the leaves and 128-cell nodes first (near),
// then the nodes above them, which take seconds. Saving
// writes the set back to the tileset on the worker (atomically: a save in progress never leaves
// a file that fails verify). One job at a time; frames never wait for one.

#include <atomic>
#include <chrono>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include "terralod/build/vipm_chunk_set.h"
#include "terralod/render/terrain_scene.h"

namespace terralod::cli {

class LiveEditor {
 public:
  explicit LiveEditor(VipmChunkSet set);
  ~LiveEditor();  ///< waits for the job in progress
  LiveEditor(const LiveEditor&) = delete;
  LiveEditor& operator=(const LiveEditor&) = delete;

  bool busy() const { return mJob != Job::kNone; }
  /// Starts applying `stroke`; false (and nothing done) while busy.
  bool submit(const TerrainEdit& stroke);
  /// Starts writing the set to `path`; false while busy.
  bool save(const std::string& path);

  struct Finished {
    enum class What : uint8_t {
      kInterim,  ///< a stroke's chunks as whole grids (the stroke goes on)
      kNear,     ///< a stroke's leaves and 128-cell nodes made (the stroke goes on)
      kStroke,   ///< a stroke's chunks made (the rest of them)
      kSave
    };
    What what = What::kStroke;
    Status status;                 ///< (kInterim, kNear: always ok)
    double ms = 0.0;               ///< the job's own time on the worker (not until it was polled)
    size_t nodes = 0;              ///< a stroke's nodes handed over
    std::vector<uint32_t> toSwap;  ///< of those, the ones the scene had drawn or on its way
    size_t inPlace = 0;            ///< drawn nodes whose record alone changed, updated in place
  };
  /// Each frame, on the drawing thread: what finished since, if anything (a stroke's nodes
  /// already handed to `scene`); a stroke's interim nodes, then its near ones, then the rest.
  std::optional<Finished> poll(TerrainScene& scene);

  size_t strokes() const { return mStrokes; }  ///< applied since it was made
  bool unsaved() const { return mUnsaved; }

 private:
  enum class Job : uint8_t { kNone, kStroke, kSave };
  using Clock = std::chrono::steady_clock;
  void start(Job job, std::function<Status()> work);

  VipmChunkSet mSet;
  Job mJob = Job::kNone;
  std::thread mWorker;
  std::atomic<bool> mDone{false};
  Status mStatus;
  Result<std::vector<uint32_t>> mChanged{std::vector<uint32_t>{}};
  // A stroke's interim nodes, written by the worker before mInterimReady.
  std::mutex mInterimMutex;
  std::vector<VipmInterimNode> mInterim;
  double mInterimMs = 0.0;
  std::atomic<bool> mInterimReady{false};
  // A stroke's leaves and roots as made, with their level errors, before mNearReady.
  std::vector<VipmInterimNode> mNear;
  std::vector<double> mNearLevelErrors;
  double mNearMs = 0.0;
  std::atomic<bool> mNearReady{false};
  std::vector<uint32_t> mNearVersions;  // their VipmChunkSet::bytesVersion
  // Per node, the bytes version the scene was handed (drawing thread): a node changed again
  // with the same version changed only its record. kWholeGrid: an interim grid.
  static constexpr uint32_t kWholeGrid = ~uint32_t{0};
  std::vector<uint32_t> mHandedVersion;
  Clock::time_point mStart;
  double mWorkMs = 0.0;  // the job's own time, written by the worker before mDone
  size_t mStrokes = 0;
  bool mUnsaved = false;
};

}  // namespace terralod::cli
