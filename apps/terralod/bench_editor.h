#pragma once
// Brush strokes during a bench flight (bench --edit-script): every `every` frames the next
// stroke goes to a LiveEditor; measured per stroke, the regeneration, and the time and frames
// from the stroke to its last leaf or root swapped in, and to its whole-grid interim chunks
// drawn; with levels above the roots, the time to those made too. Frames never wait for any.

#include <chrono>
#include <vector>

#include <nlohmann/json.hpp>

#include "live_editor.h"

namespace terralod::cli {

class BenchEditor {
 public:
  BenchEditor(VipmChunkSet set, std::vector<TerrainEdit> strokes, size_t every);

  /// Called before frame `frame` is drawn. Fails when a stroke cannot be applied.
  Status beforeFrame(size_t frame, TerrainScene& scene);
  /// "edit_strokes", "edit_swapped", "edit_regen_ms_p50/max", "edit_latency_ms_p50/max",
  /// "edit_latency_frames_p50/max", "edit_nodes_p50/max" (leaves and roots rebuilt per
  /// stroke) and "edit_resident_nodes_p50/max" (of those, the ones the scene had to swap);
  /// "edit_upper_strokes", "edit_upper_ms_p50/max" and "edit_upper_nodes_p50" (strokes that
  /// changed nodes above the roots: stroke to those made, and how many) with
  /// "edit_upper_in_place_max" (of those, drawn nodes whose record alone changed, updated in
  /// place); and
  /// "edit_interim_drawn" (strokes whose whole-grid chunks were all drawn before their made
  /// ones came) with "edit_interim_latency_ms_p50/max" and "_frames_p50/max" into `summary`.
  void addFigures(nlohmann::json& summary) const;

 private:
  using Clock = std::chrono::steady_clock;
  struct Stroke {
    Clock::time_point start;
    size_t startFrame = 0;
    double regenMs = 0.0, latencyMs = 0.0, interimMs = 0.0, upperMs = 0.0;
    size_t latencyFrames = 0, interimFrames = 0, nodes = 0, upperNodes = 0;
    size_t inPlace = 0;  // of the upper hand-over, drawn nodes that took a new record in place
    bool interimHanded = false, interimDrawn = false, regenerated = false, swapped = false;
    bool finished = false;         // the stroke's job is over (its nodes above the roots made too)
    std::vector<uint32_t> toSwap;  // its nodes last handed over that the scene had to swap
  };

  LiveEditor mEditor;
  std::vector<TerrainEdit> mStrokes;
  size_t mEvery;
  size_t mNext = 0;  // the next stroke
  std::vector<Stroke> mDone;
};

}  // namespace terralod::cli
