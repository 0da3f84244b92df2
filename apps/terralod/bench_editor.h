#pragma once
// Brush strokes during a bench flight (bench --edit-script): every `every` frames the next
// stroke goes to a worker thread, which applies it to the tileset's chunk set in memory
// (VipmChunkSet::apply); the frame after it is done, its nodes go to the scene, which swaps
// them in over the next frames. Frames never wait for either. Measured per stroke: the
// regeneration, and the time and frames from the stroke to its last chunk swapped in.

#include <atomic>
#include <memory>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "terralod/build/vipm_chunk_set.h"
#include "terralod/render/terrain_scene.h"

namespace terralod::cli {

class BenchEditor {
 public:
  BenchEditor(VipmChunkSet set, std::vector<TerrainEdit> strokes, size_t every);
  ~BenchEditor();  ///< waits for a stroke still being applied
  BenchEditor(const BenchEditor&) = delete;
  BenchEditor& operator=(const BenchEditor&) = delete;

  /// Called before frame `frame` is drawn. Fails when a stroke cannot be applied.
  Status beforeFrame(size_t frame, TerrainScene& scene);
  /// "edit_strokes", "edit_swapped", "edit_regen_ms_p50/max", "edit_latency_ms_p50/max",
  /// "edit_latency_frames_p50/max", "edit_nodes_p50/max" (nodes rebuilt per stroke) and
  /// "edit_resident_nodes_p50/max" (of those, the ones the scene had to swap) into `summary`.
  void addFigures(nlohmann::json& summary) const;

 private:
  using Clock = std::chrono::steady_clock;
  struct Stroke {
    Clock::time_point start;
    size_t startFrame = 0;
    double regenMs = 0.0, latencyMs = 0.0;
    size_t latencyFrames = 0, nodes = 0;
    size_t drawnNodes = 0;  // of those, resident (or on their way) when handed to the scene
    bool swapped = false;
  };
  enum class State : uint8_t { kIdle, kApplying, kSwapping };

  VipmChunkSet mSet;
  std::vector<TerrainEdit> mStrokes;
  size_t mEvery;
  size_t mNext = 0;  // the next stroke
  State mState = State::kIdle;
  std::thread mWorker;
  std::atomic<bool> mApplied{false};
  Result<std::vector<uint32_t>> mChanged{std::vector<uint32_t>{}};
  std::vector<Stroke> mDone;
};

}  // namespace terralod::cli
