#include "live_editor.h"

#include "terralod/build/vipm_builder.h"

namespace terralod::cli {

LiveEditor::LiveEditor(VipmChunkSet set) : mSet(std::move(set)) {}

LiveEditor::~LiveEditor() {
  if (mWorker.joinable()) mWorker.join();
}

void LiveEditor::start(Job job, std::function<Status()> work) {
  mJob = job;
  mDone = false;
  mStart = Clock::now();
  mWorker = std::thread([this, work = std::move(work)] {
    mStatus = work();
    mWorkMs = std::chrono::duration<double, std::milli>(Clock::now() - mStart).count();
    mDone = true;
  });
}

bool LiveEditor::submit(const TerrainEdit& stroke) {
  if (busy()) return false;
  start(Job::kStroke, [this, stroke]() -> Status {
    mChanged = mSet.apply(std::vector<TerrainEdit>{stroke}, 0);
    if (!mChanged) return mChanged.error();
    return {};
  });
  return true;
}

bool LiveEditor::save(const std::string& path) {
  if (busy()) return false;
  start(Job::kSave, [this, path] { return writeVipmTileset(mSet, path); });
  return true;
}

std::optional<LiveEditor::Finished> LiveEditor::poll(TerrainScene& scene) {
  if (!busy() || !mDone) return std::nullopt;
  mWorker.join();
  Finished f;
  f.stroke = mJob == Job::kStroke;
  f.status = mStatus;
  f.ms = mWorkMs;
  mJob = Job::kNone;
  if (!f.status) return f;
  if (!f.stroke) {
    mUnsaved = false;
    return f;
  }
  ++mStrokes;
  mUnsaved = true;
  std::vector<NodeReplacement> nodes;
  for (uint32_t node : *mChanged) nodes.push_back({node, mSet.nodes()[node], mSet.nodeBytes(node)});
  f.nodes = nodes.size();
  // The roots' level error may have moved; the leaves' is --max-error.
  const std::vector<double> levelErrors = {mSet.rootLevelError(), scene.tree().levelError(1)};
  scene.replaceNodes(std::move(nodes), levelErrors);
  f.drawnNodes = scene.pendingReplacements();
  return f;
}

}  // namespace terralod::cli
