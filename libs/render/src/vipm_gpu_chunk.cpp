#include "vipm_gpu_chunk.h"

#include <epoxy/gl.h>

#include <algorithm>
#include <cmath>
#include <utility>

#include "terralod/render/texture_arrays.h"

namespace terralod {

GlTexture::~GlTexture() {
  if (mName) glDeleteTextures(1, &mName);
}
GlTexture::GlTexture(GlTexture&& other) noexcept : mName(std::exchange(other.mName, 0)) {}
GlTexture& GlTexture::operator=(GlTexture&& other) noexcept {
  if (this != &other) {
    if (mName) glDeleteTextures(1, &mName);
    mName = std::exchange(other.mName, 0);
  }
  return *this;
}

VipmGpuChunk::VipmGpuChunk(const VipmChunkPayload& p)
    : mMesh(p.mesh),
      mLevels(p.levels),
      mOwn(p.positions),
      mDrawn(p.positions),
      mFade(p.fade),
      mFlanges(p.flanges),
      mFlangeDepth(p.flangeDepth),
      mWidth(p.width),
      mHeight(p.height),
      mZBase(p.zBase) {
  glCreateBuffers(GLsizei(mBuffers.size()), mBuffers.data());
  const auto positionBytes = GLsizeiptr(mOwn.size() * sizeof(mOwn[0]));
  glNamedBufferStorage(mBuffers[0], positionBytes, mOwn.data(), GL_DYNAMIC_STORAGE_BIT);
  // Materials: each vertex's own (flange copies: their top's), and its weights.
  mMaterials = p.materials;
  glNamedBufferStorage(mBuffers[1], GLsizeiptr(mMaterials.size()), mMaterials.data(), 0);
  mWeightBytes.resize(mMaterials.size());
  for (size_t v = 0; v < mMaterials.size(); ++v) {
    mWeightBytes[v].fill(0);
    mWeightBytes[v][mMaterials[v] % kMaxMaterials] = 255;
  }
  if (mFade == MaterialFade::kToTarget)
    for (uint32_t v = 0; v < mMesh.vertexCount(); ++v) mWeights.push_back(ownWeights(v));
  const auto weightBytes = GLsizeiptr(mWeightBytes.size() * sizeof(mWeightBytes[0]));
  glNamedBufferStorage(mBuffers[3], weightBytes, mWeightBytes.data(),
                       mFade == MaterialFade::kToTarget ? GL_DYNAMIC_STORAGE_BIT : 0);
  if (mFade == MaterialFade::kKeep) {  // never changes: no CPU copies needed
    mMaterials = {};
    mWeightBytes = {};
  }
  // Every part at a fixed place, at its finest level's size; the flanges after them.
  uint32_t first = 0;
  for (const VipmPart& part : mLevels.parts()) {
    mRanges.push_back({part.material, first, 0});
    first += uint32_t(part.indices.size());
  }
  mFlangeFirst = first;
  const size_t indexCount = size_t(first) + maxFlangeIndices(mFlanges);
  glNamedBufferStorage(mBuffers[2], GLsizeiptr(std::max<size_t>(indexCount, 1) * 2), nullptr,
                       GL_DYNAMIC_STORAGE_BIT);
  for (VipmPart& part : mLevels.parts()) part.dirty = true;
  // The stored BC5 normal map as it is, with its mips (as the static kind's textures).
  mNormalMap = GlTexture(uploadLayerTexture(p.normals));
  mNormalSize = p.normals.size;
  uint64_t normalBytes = 0;
  for (const auto& mip : p.normals.mips) normalBytes += mip.size();
  // On the GPU, plus the CPU state (the payload's copy and the drawn positions).
  mGpuBytes = uint64_t(positionBytes) + mMaterials.size() + uint64_t(weightBytes) + indexCount * 2 +
              normalBytes;
  mBytes = mGpuBytes + p.bytes() + uint64_t(positionBytes) + mMaterials.size() +
           mWeightBytes.size() * sizeof(mWeightBytes[0]) + mWeights.size() * sizeof(mWeights[0]);
  update(0.0, Geomorph::kOff);
}

VipmGpuChunk::~VipmGpuChunk() {
  glDeleteBuffers(GLsizei(mBuffers.size()), mBuffers.data());
}

void VipmGpuChunk::uploadPositions(uint32_t first, uint32_t count) {
  if (count == 0) return;
  glNamedBufferSubData(mBuffers[0], GLintptr(first * sizeof(mDrawn[0])),
                       GLsizeiptr(count * sizeof(mDrawn[0])), mDrawn.data() + first);
  if (mFade == MaterialFade::kToTarget)
    glNamedBufferSubData(mBuffers[3], GLintptr(first * sizeof(mWeightBytes[0])),
                         GLsizeiptr(count * sizeof(mWeightBytes[0])), mWeightBytes.data() + first);
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
  if (morphs)
    morphPositions(mMesh, window, morphTheta, std::span(mOwn).first(n), std::span(mDrawn).first(n));
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
    mRanges[i].count = mLevels.drawnTriangles(part) * 3;
    if (!part.dirty) continue;
    if (mRanges[i].count)
      glNamedBufferSubData(mBuffers[2], GLintptr(mRanges[i].firstIndex * 2),
                           GLsizeiptr(mRanges[i].count * 2), part.indices.data());
    part.dirty = false;
  }
  if (levelChanged) {
    const VipmPart& whole = mLevels.whole();
    flangeIndices(mFlanges, n, mLevels.activeVertices(),
                  std::span(whole.indices).first(size_t(mLevels.drawnTriangles(whole)) * 3),
                  mFlangeIndices);
    if (!mFlangeIndices.empty())
      glNamedBufferSubData(mBuffers[2], GLintptr(mFlangeFirst * 2),
                           GLsizeiptr(mFlangeIndices.size() * 2), mFlangeIndices.data());
    mFlangesValid = true;
  }
}

}  // namespace terralod
