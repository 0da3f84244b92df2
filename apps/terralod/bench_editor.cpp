#include "bench_editor.h"

#include "terralod/measure/bench_flight.h"

namespace terralod::cli {

BenchEditor::BenchEditor(VipmChunkSet set, std::vector<TerrainEdit> strokes, size_t every)
    : mSet(std::move(set)), mStrokes(std::move(strokes)), mEvery(std::max<size_t>(every, 1)) {}

BenchEditor::~BenchEditor() {
  if (mWorker.joinable()) mWorker.join();
}

Status BenchEditor::beforeFrame(size_t frame, TerrainScene& scene) {
  switch (mState) {
    case State::kIdle:
      if (mNext >= mStrokes.size() || frame < (mNext + 1) * mEvery) return {};
      mDone.push_back({Clock::now(), frame});
      mApplied = false;
      mWorker = std::thread([this, stroke = mStrokes[mNext]] {
        mChanged = mSet.apply(std::vector<TerrainEdit>{stroke}, 0);
        mApplied = true;
      });
      mState = State::kApplying;
      return {};
    case State::kApplying: {
      if (!mApplied) return {};
      mWorker.join();
      Stroke& s = mDone.back();
      s.regenMs = std::chrono::duration<double, std::milli>(Clock::now() - s.start).count();
      if (!mChanged) return mChanged.error();
      std::vector<NodeReplacement> nodes;
      for (uint32_t node : *mChanged)
        nodes.push_back({node, mSet.nodes()[node], mSet.nodeBytes(node)});
      s.nodes = nodes.size();
      // The roots' level error may have moved; the leaves' is --max-error.
      const std::vector<double> levelErrors = {mSet.rootLevelError(), scene.tree().levelError(1)};
      scene.replaceNodes(std::move(nodes), levelErrors);
      s.drawnNodes = scene.pendingReplacements();
      mState = State::kSwapping;
      return {};
    }
    case State::kSwapping:
      // Everything the last frame drew of the stroke's nodes was already the new chunks.
      if (scene.pendingReplacements() != 0) return {};
      Stroke& s = mDone.back();
      s.latencyMs = std::chrono::duration<double, std::milli>(Clock::now() - s.start).count();
      s.latencyFrames = frame - s.startFrame;
      s.swapped = true;
      ++mNext;
      mState = State::kIdle;
      return {};
  }
  return {};
}

void BenchEditor::addFigures(nlohmann::json& j) const {
  std::vector<double> regen, latency, frames, nodes, drawn;
  size_t swapped = 0;
  for (const Stroke& s : mDone) {
    regen.push_back(s.regenMs);
    nodes.push_back(double(s.nodes));
    drawn.push_back(double(s.drawnNodes));
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
}

}  // namespace terralod::cli
