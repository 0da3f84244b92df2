#include "vipm_gpu_chunk.h"

#include <epoxy/gl.h>

#include <algorithm>
#include <cmath>
#include <utility>

namespace terralod {

VipmGpuChunk::VipmGpuChunk(const VipmChunkPayload& p, VipmBlock& block, int slot)
    : mMesh(p.mesh),
      mLevels(p.levels),
      mStitcher(p.stitcher),
      mOwn(p.positions),
      mDrawn(p.positions),
      mFade(p.fade),
      mFlanges(p.flanges),
      mFlangeDepth(p.flangeDepth),
      mWidth(p.width),
      mHeight(p.height),
      mZBase(p.zBase),
      mBlock(block),
      mSlot(slot),
      mIndexBuffer(GlBuffer::make()) {
  static uint64_t made = 0;  // render thread only
  mSerial = ++made;
  // Vertices: the mesh's, the flange copies, then room for the fans' inserted points.
  mFanVertexFirst = uint32_t(mOwn.size());
  const size_t vertexCount = mOwn.size() + mStitcher.maxInsertedPoints();
  mDrawn.resize(vertexCount);
  mVertices = mBlock.allocate(uint32_t(vertexCount), slot);
  const auto positionBytes = vertexCount * sizeof(mDrawn[0]);
  mBlock.writePositions(mVertices, 0, mDrawn);
  // Materials: each vertex's own (flange copies: their top's), and its weights.
  mMaterials = p.materials;
  mMaterials.resize(vertexCount, 0);
  mBlock.writeMaterials(mVertices, 0, mMaterials);
  mWeightBytes.resize(mMaterials.size());
  for (size_t v = 0; v < mMaterials.size(); ++v) {
    mWeightBytes[v].fill(0);
    mWeightBytes[v][mMaterials[v] % kMaxMaterials] = 255;
  }
  if (mFade == MaterialFade::kToTarget)
    for (uint32_t v = 0; v < mMesh.vertexCount(); ++v) mWeights.push_back(ownWeights(v));
  const auto weightBytes = mWeightBytes.size() * sizeof(mWeightBytes[0]);
  mBlock.writeWeights(mVertices, 0, mWeightBytes);
  // Every part at a fixed place, at its finest level's size plus room for its fans; the
  // flanges after them.
  uint32_t first = 0;
  const uint32_t fanRoom = 3 * mStitcher.maxFanTriangles();
  for (const VipmPart& part : mLevels.parts()) {
    mRanges.push_back({part.material, first, 0});
    first += uint32_t(part.indices.size()) + fanRoom;
  }
  mReplaced.resize(mRanges.size());
  mFanOffset.assign(mRanges.size(), 0);
  mPartFans.resize(mRanges.size());
  mPrefixUploaded.assign(mRanges.size(), 0);
  mFlangeFirst = first;
  const size_t indexCount = size_t(first) + maxFlangeIndices(mFlanges);
  glNamedBufferStorage(mIndexBuffer.id(), GLsizeiptr(std::max<size_t>(indexCount, 1) * 2), nullptr,
                       GL_DYNAMIC_STORAGE_BIT);
  for (VipmPart& part : mLevels.parts()) part.dirty = true;
  // The stored BC5 normal map as it is, with its mips (as the static kind's textures), and
  // the blot texture, with mips (blots are small on screen), averaged encoded as the material
  // passes add encoded colours.
  mBlock.writeTextures(slot, p.normals, p.blot);
  mNormalSize = p.normals.size;
  mCells = p.cells;
  // On the GPU (its vertices with their one-byte slot tags, its indices, its layers), plus the
  // CPU state (the payload's copy but its textures, which only the GPU keeps; the drawn
  // positions, materials and weights).
  mBlockBytes =
      uint64_t(positionBytes) + 2 * mMaterials.size() + uint64_t(weightBytes) + mBlock.layerBytes();
  mGpuBytes = mBlockBytes + indexCount * 2;
  mBytes = mGpuBytes + p.bytes() - p.textureBytes() + uint64_t(positionBytes) + mMaterials.size() +
           mWeightBytes.size() * sizeof(mWeightBytes[0]) + mWeights.size() * sizeof(mWeights[0]);
  update(0.0, Geomorph::kOff);
}

VipmGpuChunk::~VipmGpuChunk() {
  mBlock.release(mVertices);
}

void VipmGpuChunk::setFlangeDepth(float depth) {
  if (depth == mFlangeDepth) return;
  mFlangeDepth = depth;
  const uint32_t n = mMesh.vertexCount();
  for (size_t k = 0; k < mFlanges.tops.size(); ++k) {
    mOwn[n + k] = mOwn[mFlanges.tops[k]];
    mOwn[n + k][2] -= depth;
    mDrawn[n + k] = mDrawn[mFlanges.tops[k]];
    mDrawn[n + k][2] -= depth;
  }
  uploadPositions(n, uint32_t(mFlanges.tops.size()));
}

void VipmGpuChunk::uploadPositions(uint32_t first, uint32_t count) {
  if (count == 0) return;
  mBlock.writePositions(mVertices, first, std::span(mDrawn).subspan(first, count));
  if (mFade == MaterialFade::kToTarget)
    mBlock.writeWeights(mVertices, first, std::span(mWeightBytes).subspan(first, count));
}

void VipmGpuChunk::writeIndices(uint32_t first, std::span<const uint16_t> indices) {
  if (indices.empty()) return;
  glNamedBufferSubData(mIndexBuffer.id(), GLintptr(first) * 2, GLsizeiptr(indices.size_bytes()),
                       indices.data());
  ++mIndexVersion;
}

void VipmGpuChunk::appendDrawn(std::vector<uint32_t>& surface,
                               std::vector<uint32_t>* flanges) const {
  const uint32_t base = mVertices.first;
  const VipmPart& whole = mLevels.whole();
  const uint32_t living = mLevels.drawnTriangles(whole);
  const std::vector<uint32_t>& replaced = mReplaced.front();
  auto skip = replaced.begin();
  for (uint32_t t = 0; t < living; ++t) {
    while (skip != replaced.end() && *skip < t) ++skip;
    if (skip != replaced.end() && *skip == t) continue;
    for (int k = 0; k < 3; ++k) surface.push_back(base + whole.indices[3 * t + size_t(k)]);
  }
  for (uint16_t i : mPartFans.front()) surface.push_back(base + i);
  if (flanges)
    for (uint16_t i : mFlangeIndices) flanges->push_back(base + i);
}

MaterialWeights VipmGpuChunk::ownWeights(uint32_t v) const {
  MaterialWeights w{};
  w[mMaterials[v] % kMaxMaterials] = 1.0f;
  return w;
}

void VipmGpuChunk::morphMaterials(const MorphWindow& previous, const MorphWindow& window,
                                  double morphTheta, uint32_t first, uint32_t end) {
  const uint32_t n = mMesh.vertexCount();
  for (uint32_t j = previous.applied; j < previous.morphing; ++j)
    mWeights[n - 1 - j] = ownWeights(n - 1 - j);
  morphMaterialWeights(mMesh, window, morphTheta, std::span(mMaterials).first(n), mWeights);
  for (uint32_t v = first; v < end; ++v)
    for (int m = 0; m < kMaxMaterials; ++m)
      mWeightBytes[v][size_t(m)] = uint8_t(std::lround(255.0f * mWeights[v][size_t(m)]));
  for (size_t k = 0; k < mFlanges.tops.size(); ++k)
    mWeightBytes[n + k] = mWeightBytes[mFlanges.tops[k]];
}

void VipmGpuChunk::update(double theta, double morphTheta, Geomorph geomorph) {
  const uint32_t n = mMesh.vertexCount();
  const MorphWindow window = morphWindow(mMesh.errors, theta, geomorph);
  const MorphWindow previous = mWindow;
  const bool levelChanged = window.applied != mLevels.applied() || !mFlangesValid;
  mLevels.setApplied(window.applied);

  // Vertices of collapse j sit at n - 1 - j: the windows' vertices are contiguous ranges.
  // Those that morphed go back to their own positions, then the window morphs.
  const bool morphed = previous.morphing > previous.applied;
  const bool morphs = window.morphing > window.applied;
  for (uint32_t j = previous.applied; j < previous.morphing; ++j)
    mDrawn[n - 1 - j] = mOwn[n - 1 - j];
  if (morphs) {
    morphPositions(mMesh, window, morphTheta, std::span(mOwn).first(n), std::span(mDrawn).first(n));
    // Exact in every chunk's frame, so fans elsewhere put these points where they are drawn.
    for (uint32_t j = window.applied; j < window.morphing; ++j)
      roundStitchPoint(mDrawn[n - 1 - j], mStitcher.chunk());
  }
  mWindow = window;
  if (morphed || morphs) {
    uint32_t lo = n, hi = 0;  // the union of both windows' vertex ranges
    for (const MorphWindow& w : {previous, window})
      if (w.morphing > w.applied) {
        lo = std::min(lo, n - w.morphing);
        hi = std::max(hi, n - w.applied);
      }
    if (mFade == MaterialFade::kToTarget) morphMaterials(previous, window, morphTheta, lo, hi);
    uploadPositions(lo, hi - lo);
    // Flange vertices hang below their (possibly moving) tops.
    for (size_t k = 0; k < mFlanges.tops.size(); ++k) {
      mDrawn[n + k] = mDrawn[mFlanges.tops[k]];
      mDrawn[n + k][2] -= mFlangeDepth;
    }
    uploadPositions(n, uint32_t(mFlanges.tops.size()));
  }

  // Parts whose collapse count changed: their living prefix again.
  auto parts = mLevels.parts();
  for (size_t i = 0; i < parts.size(); ++i) {
    VipmPart& part = parts[i];
    const uint32_t living = mLevels.drawnTriangles(part) * 3;
    mRanges[i].count = living;  // the fans (stitch) come after
    if (!part.dirty) continue;
    writeIndices(mRanges[i].firstIndex, std::span(part.indices).first(living));
    mPrefixUploaded[i] = 1;
    part.dirty = false;
  }
  if (levelChanged) {
    const VipmPart& whole = mLevels.whole();
    flangeIndices(mFlanges, n, mLevels.activeVertices(),
                  std::span(whole.indices).first(size_t(mLevels.drawnTriangles(whole)) * 3),
                  mFlangeIndices);
    writeIndices(mFlangeFirst, mFlangeIndices);
    mFlangesValid = true;
  }
}

void VipmGpuChunk::addStitchPoints(StitchTable& table) const {
  mStitcher.addPoints(table, mLevels.activeVertices(), std::span(mDrawn).first(mMesh.vertexCount()),
                      std::span(mWeightBytes).first(mMesh.vertexCount()),
                      std::span(mMaterials).first(mMesh.vertexCount()));
}

void VipmGpuChunk::partSlots(size_t i, std::span<const uint32_t> replaced,
                             std::vector<uint32_t>& out) const {
  out.clear();
  const VipmPart& part = mLevels.parts()[i];
  if (part.material == kWholeChunk) {
    out.assign(replaced.begin(), replaced.end());
    return;
  }
  auto from = part.wholeTriangles.begin();
  for (uint32_t t : replaced) {
    from = std::lower_bound(from, part.wholeTriangles.end(), t);
    if (from != part.wholeTriangles.end() && *from == t)
      out.push_back(uint32_t(from - part.wholeTriangles.begin()));
  }
}

bool VipmGpuChunk::fanInPart(const std::array<uint32_t, 3>& triangle, int material) const {
  if (material == kWholeChunk) return true;
  for (uint32_t v : triangle) {
    const uint32_t n = mMesh.vertexCount();
    const auto& w = v < n ? mWeightBytes[v] : mFans.weights[v - n];
    if (w[size_t(material)] > 0) return true;
  }
  return false;
}

bool VipmGpuChunk::stitch(const StitchTable* table) {
  const uint32_t n = mMesh.vertexCount();
  // The fans depend on the level and the table's points on the chunk's lines alone: when
  // those are as last time, so are the fans, and the candidate triangles are not walked.
  const uint64_t signature = table ? mStitcher.signature(*table, mLevels.applied()) : 0;
  bool changed = false;
  if (!table || signature != mFanSignature || !mFanSignatureValid) {
    StitchFans next;
    if (table) {
      const VipmPart& whole = mLevels.whole();
      mStitcher.fan(*table,
                    std::span(whole.indices).first(size_t(mLevels.drawnTriangles(whole)) * 3),
                    std::span(mDrawn).first(n), next);
    }
    changed = !(next == mFans);
    if (changed) mFans = std::move(next);
    mFanSignature = signature;
    mFanSignatureValid = table != nullptr;
  }
  if (changed) {
    // Inserted point k is vertex n + k in the fans; it is stored after the flange copies.
    const size_t k = mFans.positions.size();
    for (size_t i = 0; i < k; ++i) {
      mDrawn[mFanVertexFirst + i] = mFans.positions[i];
      mMaterials[mFanVertexFirst + i] = mFans.materials[i];
      mWeightBytes[mFanVertexFirst + i] = mFans.weights[i];
    }
    mBlock.writePositions(mVertices, mFanVertexFirst,
                          std::span(mDrawn).subspan(mFanVertexFirst, k));
    mBlock.writeMaterials(mVertices, mFanVertexFirst,
                          std::span(mMaterials).subspan(mFanVertexFirst, k));
    mBlock.writeWeights(mVertices, mFanVertexFirst,
                        std::span(mWeightBytes).subspan(mFanVertexFirst, k));
  }
  const uint32_t shift = mFanVertexFirst - n;  // inserted points sit after the flange copies
  auto parts = mLevels.parts();
  std::vector<uint32_t> slots;
  std::vector<uint16_t> fans;
  static constexpr std::array<uint16_t, 3> kEmpty{0, 0, 0};
  for (size_t i = 0; i < parts.size(); ++i) {
    const VipmPart& part = parts[i];
    const uint32_t living = mLevels.drawnTriangles(part);
    const bool placed = !changed && !mPrefixUploaded[i] && mFanOffset[i] == living * 3;
    if (placed && mFade == MaterialFade::kKeep) continue;  // its weights never change
    // A material part's fans: those with a corner weighing on it now (a root's vertices fade,
    // so this can change while the fans do not).
    fans.clear();
    for (const auto& t : mFans.triangles)
      if (fanInPart(t, part.material))
        for (uint32_t v : t) fans.push_back(uint16_t(v < n ? v : v + shift));
    if (placed && fans == mPartFans[i]) continue;
    const uint32_t base = mRanges[i].firstIndex;
    partSlots(i, mFans.replaced, slots);
    // Triangles no longer replaced get their indices back (unless the prefix was uploaded
    // whole this frame); those replaced now are emptied.
    std::vector<uint32_t>& was = mReplaced[i];
    if (!mPrefixUploaded[i])
      for (uint32_t s : was)
        if (s < living && !std::binary_search(slots.begin(), slots.end(), s))
          writeIndices(base + 3 * s, std::span(part.indices).subspan(3 * size_t(s), 3));
    for (uint32_t s : slots)
      if (mPrefixUploaded[i] || !std::binary_search(was.begin(), was.end(), s))
        writeIndices(base + 3 * s, kEmpty);
    was = slots;
    writeIndices(base + 3 * living, fans);
    mFanOffset[i] = living * 3;
    mPartFans[i] = fans;
    mPrefixUploaded[i] = 0;
  }
  for (size_t i = 0; i < parts.size(); ++i)
    mRanges[i].count = mLevels.drawnTriangles(parts[i]) * 3 + uint32_t(mPartFans[i].size());
  return changed;
}

}  // namespace terralod
