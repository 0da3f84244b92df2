#include "live_editor.h"

#include <algorithm>

#include "terralod/build/vipm_builder.h"

namespace terralod::cli {

LiveEditor::LiveEditor(VipmChunkSet set)
    : mSet(std::move(set)), mHandedVersion(mSet.nodes().size(), 0) {}

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
    auto interim = [this](std::vector<VipmInterimNode> nodes) {
      std::lock_guard lock(mInterimMutex);
      mInterim = std::move(nodes);
      mInterimMs = std::chrono::duration<double, std::milli>(Clock::now() - mStart).count();
      mInterimReady = true;
    };
    auto near = [this](std::vector<VipmInterimNode> nodes, const std::vector<double>& errors) {
      std::lock_guard lock(mInterimMutex);
      mNearVersions.clear();
      for (const VipmInterimNode& n : nodes) mNearVersions.push_back(mSet.bytesVersion(n.node));
      mNear = std::move(nodes);
      mNearLevelErrors = errors;
      mNearMs = std::chrono::duration<double, std::milli>(Clock::now() - mStart).count();
      mNearReady = true;
    };
    mChanged = mSet.apply(std::vector<TerrainEdit>{stroke}, 0, interim, near);
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

namespace {

// The tileset's level errors as drawn now, for replacements that do not change them.
std::vector<double> currentLevelErrors(const ChunkTree& tree) {
  std::vector<double> errors;
  for (int level = 0; level < tree.levelCount(); ++level) errors.push_back(tree.levelError(level));
  return errors;
}

// Hands `nodes` to the scene and notes them in `f`, with those it has to swap.
void handOver(TerrainScene& scene, std::vector<NodeReplacement> nodes,
              std::span<const double> levelErrors, LiveEditor::Finished& f) {
  std::vector<uint32_t> ids, records;
  for (const NodeReplacement& n : nodes) {
    ids.push_back(n.node);
    if (n.part == ReplacedPart::kRecord && scene.residency().state(n.node) == ChunkState::kResident)
      records.push_back(n.node);
  }
  f.nodes = nodes.size();
  scene.replaceNodes(std::move(nodes), levelErrors);
  for (uint32_t node : ids)
    if (scene.residency().stale(node)) f.toSwap.push_back(node);
  f.inPlace = size_t(std::count_if(records.begin(), records.end(),
                                   [&](uint32_t node) { return !scene.residency().stale(node); }));
}

}  // namespace

std::optional<LiveEditor::Finished> LiveEditor::poll(TerrainScene& scene) {
  if (mInterimReady && (mDone || mNearReady)) {
    // The made chunks are ready too (a stroke made within a frame): the whole grids would only
    // cost a frame and a decode more.
    std::lock_guard lock(mInterimMutex);
    mInterim.clear();
    mInterimReady = false;
  }
  if (mInterimReady) {
    Finished f;
    f.what = Finished::What::kInterim;
    std::vector<NodeReplacement> nodes;
    {
      std::lock_guard lock(mInterimMutex);
      for (VipmInterimNode& n : mInterim) {
        mHandedVersion[n.node] = kWholeGrid;
        nodes.push_back({n.node, std::move(n.record), std::move(n.bytes)});
      }
      mInterim.clear();
      f.ms = mInterimMs;
      mInterimReady = false;
    }
    handOver(scene, std::move(nodes), currentLevelErrors(scene.tree()), f);
    return f;
  }
  if (mNearReady) {
    Finished f;
    f.what = Finished::What::kNear;
    std::vector<NodeReplacement> nodes;
    std::vector<double> errors;
    {
      std::lock_guard lock(mInterimMutex);
      for (size_t k = 0; k < mNear.size(); ++k) {
        VipmInterimNode& n = mNear[k];
        mHandedVersion[n.node] = mNearVersions[k];
        nodes.push_back({n.node, std::move(n.record), std::move(n.bytes)});
      }
      mNear.clear();
      errors = std::move(mNearLevelErrors);
      f.ms = mNearMs;
      mNearReady = false;
    }
    handOver(scene, std::move(nodes), errors, f);
    return f;
  }
  if (!busy() || !mDone) return std::nullopt;
  mWorker.join();
  Finished f;
  f.what = mJob == Job::kStroke ? Finished::What::kStroke : Finished::What::kSave;
  f.status = mStatus;
  f.ms = mWorkMs;
  mJob = Job::kNone;
  if (!f.status) return f;
  if (f.what == Finished::What::kSave) {
    mUnsaved = false;
    return f;
  }
  ++mStrokes;
  mUnsaved = true;
  std::vector<NodeReplacement> nodes;
  for (uint32_t node : *mChanged) {
    // Bytes the scene has already (the build's, or handed since) and a new record: a flange
    // depth moved beside the stroke, which drawn chunks take in place.
    const uint32_t version = mSet.bytesVersion(node);
    const ReplacedPart part =
        mHandedVersion[node] == version ? ReplacedPart::kRecord : ReplacedPart::kBytes;
    mHandedVersion[node] = version;
    nodes.push_back({node, mSet.nodes()[node], mSet.nodeBytes(node), part});
  }
  // The levels above the leaves may have moved their errors; the leaves' is --max-error.
  handOver(scene, std::move(nodes), mSet.levelErrors(), f);
  return f;
}

}  // namespace terralod::cli
