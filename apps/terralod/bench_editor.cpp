#include "bench_editor.h"

#include <algorithm>

#include "terralod/measure/bench_flight.h"

namespace terralod::cli {

BenchEditor::BenchEditor(VipmChunkSet set, std::vector<TerrainEdit> strokes, size_t every)
    : mEditor(std::move(set)), mStrokes(std::move(strokes)), mEvery(std::max<size_t>(every, 1)) {}

Status BenchEditor::beforeFrame(size_t frame, TerrainScene& scene) {
  auto since = [](const Stroke& s) {
    return std::chrono::duration<double, std::milli>(Clock::now() - s.start).count();
  };
  // Whether the stroke's last nodes handed over to swap are drawn (others' may still come).
  auto drawnNew = [&](const Stroke& s) {
    return std::none_of(s.toSwap.begin(), s.toSwap.end(),
                        [&](uint32_t node) { return scene.residency().stale(node); });
  };
  // Everything the last frame drew of the interim nodes was already the interim chunks.
  if (!mDone.empty() && mDone.back().interimHanded && !mDone.back().regenerated &&
      !mDone.back().interimDrawn && drawnNew(mDone.back())) {
    Stroke& s = mDone.back();
    s.interimMs = since(s);
    s.interimFrames = frame - s.startFrame;
    s.interimDrawn = true;
  }
  if (auto finished = mEditor.poll(scene)) {
    if (!finished->status) return finished->status;
    Stroke& s = mDone.back();
    using What = LiveEditor::Finished::What;
    if (finished->what == What::kInterim) {
      s.interimHanded = true;
      s.toSwap = finished->toSwap;
    } else if (finished->what == What::kNear || !s.regenerated) {
      // The leaves and roots (with levels above them, before those; else all at once).
      s.regenMs = finished->ms;
      s.nodes = finished->nodes;
      s.toSwap = finished->toSwap;
      s.regenerated = true;
      s.finished = finished->what == What::kStroke;
    } else {
      s.upperMs = finished->ms;
      s.upperNodes = finished->nodes;
      s.inPlace = finished->inPlace;
      s.finished = true;
    }
  }
  if (!mDone.empty() && mDone.back().regenerated && !mDone.back().swapped &&
      drawnNew(mDone.back())) {
    // Everything the last frame drew of the stroke's nodes was already the new chunks.
    Stroke& s = mDone.back();
    s.latencyMs = since(s);
    s.latencyFrames = frame - s.startFrame;
    s.swapped = true;
    ++mNext;
  }
  const bool idle = mDone.empty() || (mDone.back().swapped && mDone.back().finished);
  if (idle && mNext < mStrokes.size() && frame >= (mNext + 1) * mEvery) {
    Stroke& s = mDone.emplace_back();
    s.start = Clock::now();
    s.startFrame = frame;
    mEditor.submit(mStrokes[mNext]);
  }
  return {};
}

void BenchEditor::addFigures(nlohmann::json& j) const {
  std::vector<double> regen, latency, frames, nodes, drawn, interim, interimFrames, upper,
      upperNodes, inPlace;
  size_t swapped = 0;
  for (const Stroke& s : mDone) {
    if (s.interimDrawn) {
      interim.push_back(s.interimMs);
      interimFrames.push_back(double(s.interimFrames));
    }
    if (s.upperNodes > 0) {
      upper.push_back(s.upperMs);
      upperNodes.push_back(double(s.upperNodes));
      inPlace.push_back(double(s.inPlace));
    }
    if (!s.regenerated) continue;
    regen.push_back(s.regenMs);
    nodes.push_back(double(s.nodes));
    drawn.push_back(double(s.toSwap.size()));
    if (!s.swapped) continue;
    ++swapped;
    latency.push_back(s.latencyMs);
    frames.push_back(double(s.latencyFrames));
  }
  auto max = [](const std::vector<double>& v) { return percentile(v, 1.0); };
  j["edit_strokes"] = mDone.size();
  j["edit_swapped"] = swapped;
  j["edit_regen_ms_p50"] = percentile(regen, 0.5);
  j["edit_regen_ms_max"] = max(regen);
  j["edit_latency_ms_p50"] = percentile(latency, 0.5);
  j["edit_latency_ms_max"] = max(latency);
  j["edit_latency_frames_p50"] = percentile(frames, 0.5);
  j["edit_latency_frames_max"] = max(frames);
  j["edit_nodes_p50"] = percentile(nodes, 0.5);
  j["edit_nodes_max"] = max(nodes);
  j["edit_resident_nodes_p50"] = percentile(drawn, 0.5);
  j["edit_resident_nodes_max"] = max(drawn);
  j["edit_upper_strokes"] = upper.size();
  j["edit_upper_ms_p50"] = percentile(upper, 0.5);
  j["edit_upper_ms_max"] = max(upper);
  j["edit_upper_nodes_p50"] = percentile(upperNodes, 0.5);
  j["edit_upper_in_place_max"] = max(inPlace);
  j["edit_interim_drawn"] = interim.size();
  j["edit_interim_latency_ms_p50"] = percentile(interim, 0.5);
  j["edit_interim_latency_ms_max"] = max(interim);
  j["edit_interim_latency_frames_p50"] = percentile(interimFrames, 0.5);
  j["edit_interim_latency_frames_max"] = max(interimFrames);
}

}  // namespace terralod::cli
