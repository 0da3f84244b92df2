#include "terralod/render/gpu_chunk_store.h"

#include <epoxy/gl.h>

#include <algorithm>
#include <cassert>

namespace terralod {
namespace {

constexpr size_t kVertexBytes = sizeof(ChunkVertex);
constexpr size_t kIndexBytes = sizeof(uint16_t);

uint32_t makeBuffer(uint64_t bytes) {
  GLuint buffer = 0;
  glCreateBuffers(1, &buffer);
  glNamedBufferStorage(buffer, GLsizeiptr(bytes), nullptr, GL_DYNAMIC_STORAGE_BIT);
  return buffer;
}

}  // namespace

GpuChunkStore::GpuChunkStore(uint64_t initialBytes)
    : mVertices(std::max<uint64_t>(initialBytes / 2 / kVertexBytes, 1024)),
      mIndices(std::max<uint64_t>(initialBytes / 2 / kIndexBytes, 4096)) {
  mVertexBuffer = makeBuffer(mVertices.capacity() * kVertexBytes);
  mIndexBuffer = makeBuffer(mIndices.capacity() * kIndexBytes);
}

GpuChunkStore::~GpuChunkStore() {
  const GLuint buffers[2] = {mVertexBuffer, mIndexBuffer};
  glDeleteBuffers(2, buffers);
}

uint64_t GpuChunkStore::allocate(RangeAllocator& allocator, uint32_t& buffer, uint64_t count,
                                 size_t unit) {
  if (count == 0) return 0;
  if (auto offset = allocator.allocate(count)) return *offset;
  // Full: a buffer twice as large (at least large enough), the old contents copied over.
  const uint64_t capacity = allocator.capacity();
  const uint64_t grown = std::max(capacity * 2, capacity + count);
  const uint32_t bigger = makeBuffer(grown * unit);
  glCopyNamedBufferSubData(buffer, bigger, 0, 0, GLsizeiptr(capacity * unit));
  glDeleteBuffers(1, &buffer);
  buffer = bigger;
  allocator.grow(grown - capacity);
  const auto offset = allocator.allocate(count);
  assert(offset);
  return *offset;
}

void GpuChunkStore::upload(uint32_t node, const ChunkGeometry& geometry,
                           const ChunkTexture* texture) {
  release(node);
  GpuChunk chunk;
  chunk.zBase = geometry.zBase;
  chunk.zStep = geometry.zStep;
  std::vector<uint16_t> indices;
  for (const ChunkPart& part : geometry.parts) {
    assert(part.vertices.size() <= 65536);
    GpuChunkPart p;
    p.vertexCount = uint32_t(part.vertices.size());
    p.indexCount = uint32_t(part.indices.size());
    p.surfaceIndexCount = part.surfaceIndexCount;
    p.baseVertex = uint32_t(allocate(mVertices, mVertexBuffer, p.vertexCount, kVertexBytes));
    p.firstIndex = uint32_t(allocate(mIndices, mIndexBuffer, p.indexCount, kIndexBytes));
    glNamedBufferSubData(mVertexBuffer, GLintptr(uint64_t(p.baseVertex) * kVertexBytes),
                         GLsizeiptr(p.vertexCount * kVertexBytes), part.vertices.data());
    indices.assign(part.indices.begin(), part.indices.end());  // 32 to 16 bits
    glNamedBufferSubData(mIndexBuffer, GLintptr(uint64_t(p.firstIndex) * kIndexBytes),
                         GLsizeiptr(p.indexCount * kIndexBytes), indices.data());
    chunk.bytes += uint64_t(p.vertexCount) * kVertexBytes + uint64_t(p.indexCount) * kIndexBytes;
    chunk.parts.push_back(p);
  }
  if (texture) {
    const TextureLayer* color = texture->find(TextureLayerKind::kColor);
    const TextureLayer* normal = texture->find(TextureLayerKind::kNormal);
    assert(color && normal);
    chunk.textured = true;
    chunk.color = mTextures.upload(*color);
    chunk.normal = mTextures.upload(*normal);
    chunk.bytes +=
        mTextures.layerBytes(chunk.color.array) + mTextures.layerBytes(chunk.normal.array);
  }
  mResidentBytes += chunk.bytes;
  mChunks.emplace(node, std::move(chunk));
}

bool GpuChunkStore::reserve(const ChunkTexture* texture) {
  if (!texture) return true;
  bool ok = true;
  for (TextureLayerKind kind : {TextureLayerKind::kColor, TextureLayerKind::kNormal})
    if (const TextureLayer* layer = texture->find(kind))
      ok = mTextures.reserve(layer->encoding, layer->size) && ok;  // ask for every missing page
  return ok;
}

void GpuChunkStore::release(uint32_t node) {
  auto it = mChunks.find(node);
  if (it == mChunks.end()) return;
  for (const GpuChunkPart& p : it->second.parts) {
    if (p.vertexCount) mVertices.release(p.baseVertex, p.vertexCount);
    if (p.indexCount) mIndices.release(p.firstIndex, p.indexCount);
  }
  if (it->second.textured) {
    mTextures.release(it->second.color);
    mTextures.release(it->second.normal);
  }
  mResidentBytes -= it->second.bytes;
  mChunks.erase(it);
}

const GpuChunk* GpuChunkStore::find(uint32_t node) const {
  auto it = mChunks.find(node);
  return it == mChunks.end() ? nullptr : &it->second;
}

}  // namespace terralod
