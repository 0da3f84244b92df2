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
      mStitcher(p.stitcher),
      mOwn(p.positions),
      mDrawn(p.positions),
      mFade(p.fade),
      mFlanges(p.flanges),
      mFlangeDepth(p.flangeDepth),
      mWidth(p.width),
      mHeight(p.height),
      mZBase(p.zBase) {
  // Vertices: the mesh's, the flange copies, then room for the fans' inserted points.
  mFanVertexFirst = uint32_t(mOwn.size());
  const size_t vertexCount = mOwn.size() + mStitcher.maxInsertedPoints();
  mDrawn.resize(vertexCount);
  glCreateBuffers(GLsizei(mBuffers.size()), mBuffers.data());
  const auto positionBytes = GLsizeiptr(vertexCount * sizeof(mDrawn[0]));
  glNamedBufferStorage(mBuffers[0], positionBytes, mDrawn.data(), GL_DYNAMIC_STORAGE_BIT);
  // Materials: each vertex's own (flange copies: their top's), and its weights.
  mMaterials = p.materials;
  mMaterials.resize(vertexCount, 0);
  glNamedBufferStorage(mBuffers[1], GLsizeiptr(mMaterials.size()), mMaterials.data(),
                       GL_DYNAMIC_STORAGE_BIT);
  mWeightBytes.resize(mMaterials.size());
  for (size_t v = 0; v < mMaterials.size(); ++v) {
    mWeightBytes[v].fill(0);
    mWeightBytes[v][mMaterials[v] % kMaxMaterials] = 255;
  }
  if (mFade == MaterialFade::kToTarget)
    for (uint32_t v = 0; v < mMesh.vertexCount(); ++v) mWeights.push_back(ownWeights(v));
  const auto weightBytes = GLsizeiptr(mWeightBytes.size() * sizeof(mWeightBytes[0]));
  glNamedBufferStorage(mBuffers[3], weightBytes, mWeightBytes.data(), GL_DYNAMIC_STORAGE_BIT);
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
  glNamedBufferStorage(mBuffers[2], GLsizeiptr(std::max<size_t>(indexCount, 1) * 2), nullptr,
                       GL_DYNAMIC_STORAGE_BIT);
  for (VipmPart& part : mLevels.parts()) part.dirty = true;
  // The stored BC5 normal map as it is, with its mips (as the static kind's textures).
  mNormalMap = GlTexture(uploadLayerTexture(p.normals));
  mNormalSize = p.normals.size;
  uint64_t normalBytes = 0;
  for (const auto& mip : p.normals.mips) normalBytes += mip.size();
  // The blot texture, with mips (blots are small on screen), averaged encoded as the
  // material passes add encoded colours.
  {
    GLuint name = 0;
    glCreateTextures(GL_TEXTURE_2D, 1, &name);
    mBlot = GlTexture(name);
    const auto side = GLsizei(p.normals.size);
    const int levels = int(std::floor(std::log2(double(side)))) + 1;
    glTextureStorage2D(name, levels, GL_RGBA8, side, side);  // encoded: see vipm_blot.h
    glTextureSubImage2D(name, 0, 0, 0, side, side, GL_RGBA, GL_UNSIGNED_BYTE, p.blot.data());
    glGenerateTextureMipmap(name);
    glTextureParameteri(name, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
    glTextureParameteri(name, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTextureParameteri(name, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTextureParameteri(name, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    normalBytes += p.blot.size() * 4 / 3;  // with its mips
  }
  // On the GPU, plus the CPU state (the payload's copy but its textures, which only the GPU
  // keeps; the drawn positions, materials and weights).
  mGpuBytes = uint64_t(positionBytes) + mMaterials.size() + uint64_t(weightBytes) + indexCount * 2 +
              normalBytes;
  mBytes = mGpuBytes + p.bytes() - p.textureBytes() + uint64_t(positionBytes) + mMaterials.size() +
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
  if (morphs) {
    morphPositions(mMesh, window, morphTheta, std::span(mOwn).first(n), std::span(mDrawn).first(n));
    // Exact in every chunk's frame, so fans elsewhere put these points where they are drawn.
    for (uint32_t j = window.applied; j < window.morphing; ++j) quantizeDrawn(mDrawn[n - 1 - j]);
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
    if (living)
      glNamedBufferSubData(mBuffers[2], GLintptr(mRanges[i].firstIndex * 2), GLsizeiptr(living * 2),
                           part.indices.data());
    mPrefixUploaded[i] = 1;
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
    if (k) {
      glNamedBufferSubData(mBuffers[0], GLintptr(mFanVertexFirst * sizeof(mDrawn[0])),
                           GLsizeiptr(k * sizeof(mDrawn[0])), mDrawn.data() + mFanVertexFirst);
      glNamedBufferSubData(mBuffers[1], GLintptr(mFanVertexFirst), GLsizeiptr(k),
                           mMaterials.data() + mFanVertexFirst);
      glNamedBufferSubData(mBuffers[3], GLintptr(mFanVertexFirst * sizeof(mWeightBytes[0])),
                           GLsizeiptr(k * sizeof(mWeightBytes[0])),
                           mWeightBytes.data() + mFanVertexFirst);
    }
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
    const GLintptr base = GLintptr(mRanges[i].firstIndex) * 2;
    partSlots(i, mFans.replaced, slots);
    // Triangles no longer replaced get their indices back (unless the prefix was uploaded
    // whole this frame); those replaced now are emptied.
    std::vector<uint32_t>& was = mReplaced[i];
    if (!mPrefixUploaded[i])
      for (uint32_t s : was)
        if (s < living && !std::binary_search(slots.begin(), slots.end(), s))
          glNamedBufferSubData(mBuffers[2], base + GLintptr(s) * 6, 6, part.indices.data() + 3 * s);
    for (uint32_t s : slots)
      if (mPrefixUploaded[i] || !std::binary_search(was.begin(), was.end(), s))
        glNamedBufferSubData(mBuffers[2], base + GLintptr(s) * 6, 6, kEmpty.data());
    was = slots;
    if (!fans.empty())
      glNamedBufferSubData(mBuffers[2], base + GLintptr(living) * 6, GLsizeiptr(fans.size() * 2),
                           fans.data());
    mFanOffset[i] = living * 3;
    mPartFans[i] = fans;
    mPrefixUploaded[i] = 0;
  }
  for (size_t i = 0; i < parts.size(); ++i)
    mRanges[i].count = mLevels.drawnTriangles(parts[i]) * 3 + uint32_t(mPartFans[i].size());
  return changed;
}

}  // namespace terralod
