#pragma once
// Owning handles for the GL buffers and vertex arrays the render passes keep, so the passes
// move and die without hand-written bookkeeping. Render thread only.

#include <epoxy/gl.h>

#include <algorithm>
#include <cstdint>
#include <utility>
#include <vector>

namespace terralod {

enum class GlObjectKind { kBuffer, kVertexArray };

template <GlObjectKind Kind>
class GlObject {
 public:
  GlObject() = default;
  /// Creates a new object of its kind.
  static GlObject make() {
    GlObject object;
    if constexpr (Kind == GlObjectKind::kBuffer)
      glCreateBuffers(1, &object.mName);
    else
      glCreateVertexArrays(1, &object.mName);
    return object;
  }
  ~GlObject() { reset(); }
  GlObject(GlObject&& other) noexcept : mName(std::exchange(other.mName, 0)) {}
  GlObject& operator=(GlObject&& other) noexcept {
    if (this != &other) {
      reset();
      mName = std::exchange(other.mName, 0);
    }
    return *this;
  }
  GlObject(const GlObject&) = delete;
  GlObject& operator=(const GlObject&) = delete;

  uint32_t id() const { return mName; }
  void reset() {
    if (mName == 0) return;
    if constexpr (Kind == GlObjectKind::kBuffer)
      glDeleteBuffers(1, &mName);
    else
      glDeleteVertexArrays(1, &mName);
    mName = 0;
  }

 private:
  uint32_t mName = 0;
};

using GlBuffer = GlObject<GlObjectKind::kBuffer>;
using GlVertexArray = GlObject<GlObjectKind::kVertexArray>;

/// A texture name (made by the caller with glCreateTextures), deleted with its owner.
class GlTexture {
 public:
  GlTexture() = default;
  explicit GlTexture(uint32_t name) : mName(name) {}
  ~GlTexture() {
    if (mName) glDeleteTextures(1, &mName);
  }
  GlTexture(GlTexture&& other) noexcept : mName(std::exchange(other.mName, 0)) {}
  GlTexture& operator=(GlTexture&& other) noexcept {
    if (this != &other) {
      if (mName) glDeleteTextures(1, &mName);
      mName = std::exchange(other.mName, 0);
    }
    return *this;
  }
  GlTexture(const GlTexture&) = delete;
  GlTexture& operator=(const GlTexture&) = delete;
  uint32_t id() const { return mName; }

 private:
  uint32_t mName = 0;
};

/// A buffer refilled every frame: reallocated (twice the size asked, at least 4 KB) only
/// when the data outgrows it.
class GrowingBuffer {
 public:
  template <typename T>
  void upload(const std::vector<T>& data) {
    const uint64_t bytes = data.size() * sizeof(T);
    if (bytes > mCapacity) {
      mCapacity = std::max<uint64_t>(bytes * 2, 4096);
      mBuffer = GlBuffer::make();
      glNamedBufferStorage(mBuffer.id(), GLsizeiptr(mCapacity), nullptr, GL_DYNAMIC_STORAGE_BIT);
    }
    if (bytes) glNamedBufferSubData(mBuffer.id(), 0, GLsizeiptr(bytes), data.data());
  }
  uint32_t id() const { return mBuffer.id(); }

 private:
  GlBuffer mBuffer;
  uint64_t mCapacity = 0;
};

}  // namespace terralod
