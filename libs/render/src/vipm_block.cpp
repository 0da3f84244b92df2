#include "vipm_block.h"

#include <epoxy/gl.h>

#include <algorithm>
#include <cassert>
#include <cmath>

#include "terralod/render/texture_arrays.h"

namespace terralod {
namespace {

GLuint makeArray(GLenum format, uint32_t size, uint32_t levels) {
  GLuint t = 0;
  glCreateTextures(GL_TEXTURE_2D_ARRAY, 1, &t);
  glTextureStorage3D(t, GLsizei(levels), format, GLsizei(size), GLsizei(size), VipmBlock::kSlots);
  setChunkTextureSampling(t);
  return t;
}

}  // namespace

VipmBlock::VipmBlock(uint32_t normalSize, TextureEncoding normalEncoding, uint32_t normalLevels)
    : mNormalSize(normalSize),
      mNormalLevels(normalLevels),
      mBlotLevels(uint32_t(std::floor(std::log2(double(std::max(normalSize, 1u))))) + 1),
      mNormalEncoding(normalEncoding) {
  mNormals = GlTexture(makeArray(chunkTextureFormat(normalEncoding), normalSize, normalLevels));
  mBlots = GlTexture(makeArray(GL_RGBA8, normalSize, mBlotLevels));  // encoded: vipm_blot.h
}

bool VipmBlock::fits(const TextureLayer& normals) const {
  return normals.size == mNormalSize && normals.encoding == mNormalEncoding &&
         normals.mips.size() == mNormalLevels;
}

uint64_t VipmBlock::layerBytes() const {
  uint64_t layer = 0;
  for (uint32_t m = 0; m < mNormalLevels; ++m) layer += mipBytes(mNormalEncoding, mNormalSize, m);
  for (uint32_t m = 0; m < mBlotLevels; ++m) {
    const uint64_t side = std::max(mNormalSize >> m, 1u);
    layer += side * side * 4;  // RGBA8
  }
  return layer;
}

uint64_t VipmBlock::allocatedBytes() const {
  uint64_t vertexBytes = 0;
  for (uint32_t unit : kUnit) vertexBytes += mRanges.capacity() * unit;
  return vertexBytes + layerBytes() * kSlots;
}

bool VipmBlock::empty() const {
  return std::all_of(mMembers.begin(), mMembers.end(), [](auto* m) { return m == nullptr; });
}

void VipmBlock::grow(uint32_t needed) {
  const uint64_t old = mRanges.capacity();
  // Room for the rest of the block's chunks at about this one's size, then by half again.
  const uint64_t capacity =
      old == 0 ? uint64_t(needed) * kSlots : std::max(old + old / 2, old + needed);
  for (size_t i = 0; i < mBuffers.size(); ++i) {
    GlBuffer next = GlBuffer::make();
    glNamedBufferStorage(next.id(), GLsizeiptr(capacity * kUnit[i]), nullptr,
                         GL_DYNAMIC_STORAGE_BIT);
    if (old)
      glCopyNamedBufferSubData(mBuffers[i].id(), next.id(), 0, 0, GLsizeiptr(old * kUnit[i]));
    mBuffers[i] = std::move(next);
  }
  mRanges.grow(capacity - old);
}

VipmVertexRange VipmBlock::allocate(uint32_t count, int slot) {
  count = std::max(count, 1u);
  auto first = mRanges.allocate(count);
  if (!first) {
    grow(count);
    first = mRanges.allocate(count);
    assert(first);
  }
  const VipmVertexRange range{uint32_t(*first), count};
  const std::vector<uint8_t> slots(count, uint8_t(slot));
  write(3, range, 0, std::span<const uint8_t>(slots));
  return range;
}

void VipmBlock::release(VipmVertexRange range) {
  if (range.count) mRanges.release(range.first, range.count);
}

template <typename T>
void VipmBlock::write(size_t buffer, VipmVertexRange range, uint32_t first,
                      std::span<const T> values) {
  static_assert(sizeof(T) <= 12);
  assert(sizeof(T) == kUnit[buffer] && first + values.size() <= range.count);
  if (!values.empty())
    glNamedBufferSubData(mBuffers[buffer].id(), GLintptr((range.first + first) * kUnit[buffer]),
                         GLsizeiptr(values.size_bytes()), values.data());
}

void VipmBlock::writePositions(VipmVertexRange range, uint32_t first,
                               std::span<const std::array<float, 3>> values) {
  write(0, range, first, values);
}

void VipmBlock::writeMaterials(VipmVertexRange range, uint32_t first,
                               std::span<const uint8_t> values) {
  write(1, range, first, values);
}

void VipmBlock::writeWeights(VipmVertexRange range, uint32_t first,
                             std::span<const std::array<uint8_t, 8>> values) {
  write(2, range, first, values);
}

void VipmBlock::writeTextures(int slot, const TextureLayer& normals,
                              std::span<const uint8_t> blot) {
  assert(fits(normals));
  const GLenum format = chunkTextureFormat(mNormalEncoding);
  for (uint32_t m = 0; m < mNormalLevels; ++m) {
    const GLsizei s = GLsizei(mipSize(mNormalSize, m));
    glCompressedTextureSubImage3D(mNormals.id(), GLint(m), 0, 0, slot, s, s, 1, format,
                                  GLsizei(normals.mips[m].size()), normals.mips[m].data());
  }
  const auto side = GLsizei(mNormalSize);
  glTextureSubImage3D(mBlots.id(), 0, 0, 0, slot, side, side, 1, GL_RGBA, GL_UNSIGNED_BYTE,
                      blot.data());
  // Its mips alone, through a view of its layer.
  GLuint view = 0;
  glGenTextures(1, &view);
  glTextureView(view, GL_TEXTURE_2D, mBlots.id(), GL_RGBA8, 0, mBlotLevels, GLuint(slot), 1);
  glGenerateTextureMipmap(view);
  glDeleteTextures(1, &view);
}

}  // namespace terralod
