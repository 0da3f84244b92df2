#include "terralod/runtime/chunk_kind.h"

#include <algorithm>

namespace terralod {

void ChunkKinds::add(ChunkKind& kind) {
  std::erase_if(mKinds, [&](const ChunkKind* k) { return k->meshKind() == kind.meshKind(); });
  mKinds.push_back(&kind);
}

const ChunkKind* ChunkKinds::find(MeshKind kind) const {
  for (const ChunkKind* k : mKinds)
    if (k->meshKind() == kind) return k;
  return nullptr;
}

ChunkKind* ChunkKinds::find(MeshKind kind) {
  for (ChunkKind* k : mKinds)
    if (k->meshKind() == kind) return k;
  return nullptr;
}

Status ChunkKinds::covers(const ChunkTree& tree, const std::string& name) const {
  for (const ChunkNode& n : tree.nodes())
    if (!find(n.meshKind))
      return makeError(name,
                       "no kind registered for mesh kind " + std::to_string(unsigned(n.meshKind)));
  return {};
}

void KindRuns::split(const ChunkTree& tree, std::span<const SelectedChunk> chunks) {
  mRuns.clear();
  if (chunks.empty()) return;
  const MeshKind first = tree.node(chunks.front().node).meshKind;
  const bool oneKind = std::all_of(chunks.begin(), chunks.end(), [&](const SelectedChunk& c) {
    return tree.node(c.node).meshKind == first;
  });
  if (oneKind) {
    mRuns.push_back({first, chunks});
    return;
  }
  mGrouped.assign(chunks.begin(), chunks.end());
  std::stable_sort(mGrouped.begin(), mGrouped.end(),
                   [&](const SelectedChunk& a, const SelectedChunk& b) {
                     return tree.node(a.node).meshKind < tree.node(b.node).meshKind;
                   });
  const std::span<const SelectedChunk> all(mGrouped);
  size_t begin = 0;
  for (size_t i = 1; i <= all.size(); ++i) {
    const MeshKind kind = tree.node(all[begin].node).meshKind;
    if (i == all.size() || tree.node(all[i].node).meshKind != kind) {
      mRuns.push_back({kind, all.subspan(begin, i - begin)});
      begin = i;
    }
  }
}

}  // namespace terralod
