#include "terralod/render/gpu_chunk_store.h"

#include <epoxy/gl.h>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <unordered_map>

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

// Skirt bottoms of a part: the vertices only skirt triangles use that lie below another
// vertex at the same grid point (their top). The builder appends them after the surface's, so
// they are the part's last vertices. Sets firstSkirtVertex (vertexCount if that does not hold)
// and the shallowest skirt depth.
void findSkirtBottoms(const ChunkPart& part, GpuChunkPart& p) {
  p.firstSkirtVertex = p.vertexCount;
  p.skirtDepthSteps = 0;
  const size_t n = part.vertices.size();
  std::vector<uint8_t> surface(n, 0);
  for (uint32_t k = 0; k < part.surfaceIndexCount; ++k) surface[part.indices[k]] = 1;
  std::unordered_map<uint32_t, uint16_t> top;  // grid point -> highest z there
  for (const ChunkVertex& v : part.vertices) {
    auto [it, added] = top.try_emplace(uint32_t(v.x) << 16 | v.y, v.z);
    if (!added) it->second = std::max(it->second, v.z);
  }
  auto isBottom = [&](uint32_t i) {
    const ChunkVertex& v = part.vertices[i];
    return !surface[i] && top.at(uint32_t(v.x) << 16 | v.y) > v.z;
  };
  uint32_t first = uint32_t(n);
  while (first > 0 && isBottom(first - 1)) --first;
  if (first == n) return;
  for (uint32_t i = 0; i < first; ++i)
    if (isBottom(i)) return;  // not at the end: no slant for this part
  uint32_t shallowest = UINT32_MAX;
  for (uint32_t i = first; i < n; ++i) {
    const ChunkVertex& v = part.vertices[i];
    shallowest = std::min<uint32_t>(shallowest, top.at(uint32_t(v.x) << 16 | v.y) - v.z);
  }
  p.firstSkirtVertex = first;
  p.skirtDepthSteps = shallowest;
}

}  // namespace

GpuChunkStore::GpuChunkStore(uint64_t initialBytes)
    : mVertices(std::max<uint64_t>(initialBytes / 2 / kVertexBytes, 1024), kVertexBytes),
      mIndices(std::max<uint64_t>(initialBytes / 2 / kIndexBytes, 4096), kIndexBytes) {
  mVertices.name = makeBuffer(mVertices.ranges.capacity() * kVertexBytes);
  mIndices.name = makeBuffer(mIndices.ranges.capacity() * kIndexBytes);
}

GpuChunkStore::~GpuChunkStore() {
  for (Buffer* b : {&mVertices, &mIndices}) {
    glDeleteBuffers(1, &b->name);
    // A successor the worker finished but nobody adopted (the worker stops before this).
    if (b->pending && b->pending->done() && *b->pendingName)
      glDeleteBuffers(1, b->pendingName.get());
  }
}

void GpuChunkStore::setWorker(GlWorker* worker) {
  mWorker = worker;
  mTextures.setWorker(worker);
}

void GpuChunkStore::requestGrowth(Buffer& b) {
  if (!mWorker || b.pending) return;
  b.pendingCapacity = b.ranges.capacity() * 2;
  b.pendingName = std::make_shared<uint32_t>(0);
  b.pending = mWorker->post([name = b.pendingName, bytes = b.pendingCapacity * b.unit] {
    *name = makeBuffer(bytes);
    // Drivers may commit memory only when it is first written: write it here, not on the
    // render thread.
    glClearNamedBufferData(*name, GL_R8UI, GL_RED_INTEGER, GL_UNSIGNED_BYTE, nullptr);
  });
}

void GpuChunkStore::adopt(Buffer& b, uint32_t bigger, uint64_t capacity) {
  const uint64_t old = b.ranges.capacity();
  glCopyNamedBufferSubData(b.name, bigger, 0, 0, GLsizeiptr(old * b.unit));
  glDeleteBuffers(1, &b.name);
  b.name = bigger;
  b.ranges.grow(capacity - old);
}

void GpuChunkStore::poll() {
  mTextures.poll();
  for (Buffer* b : {&mVertices, &mIndices}) {
    if (!b->pending || !b->pending->done()) continue;
    adopt(*b, *b->pendingName, b->pendingCapacity);
    b->pending.reset();
    b->pendingName.reset();
  }
}

uint64_t GpuChunkStore::allocate(Buffer& b, uint64_t count) {
  if (count == 0) return 0;
  auto offset = b.ranges.allocate(count);
  if (!offset) {
    // Full: a buffer twice as large (at least large enough), made here, the old contents
    // copied over.
    const uint64_t capacity = b.ranges.capacity();
    const uint64_t grown = std::max(capacity * 2, capacity + count);
    adopt(b, makeBuffer(grown * b.unit), grown);
    offset = b.ranges.allocate(count);
    assert(offset);
  }
  // Half full: the next buffer is made ahead, off this thread.
  if (b.ranges.used() * 2 > b.ranges.capacity()) requestGrowth(b);
  return *offset;
}

bool GpuChunkStore::reserve(const ChunkGeometry& geometry, const ChunkTexture* texture) {
  bool ok = true;
  if (mWorker) {
    uint64_t vertices = 0, indices = 0;
    for (const ChunkPart& part : geometry.parts) {
      vertices += part.vertices.size();
      indices += part.indices.size();
    }
    for (auto [b, count] : {std::pair{&mVertices, vertices}, std::pair{&mIndices, indices}})
      if (b->ranges.capacity() - b->ranges.used() < count + count / 4) {  // (fragmentation)
        requestGrowth(*b);
        ok = false;
      }
  }
  if (texture)
    for (const TextureLayer* layer :
         {texture->colourSource(), texture->find(TextureLayerKind::kNormal)})
      if (layer) ok = mTextures.reserve(layer->encoding, layer->size) && ok;  // every missing page
  return ok;
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
    findSkirtBottoms(part, p);
    p.baseVertex = uint32_t(allocate(mVertices, p.vertexCount));
    p.firstIndex = uint32_t(allocate(mIndices, p.indexCount));
    glNamedBufferSubData(mVertices.name, GLintptr(uint64_t(p.baseVertex) * kVertexBytes),
                         GLsizeiptr(p.vertexCount * kVertexBytes), part.vertices.data());
    indices.assign(part.indices.begin(), part.indices.end());  // 32 to 16 bits
    glNamedBufferSubData(mIndices.name, GLintptr(uint64_t(p.firstIndex) * kIndexBytes),
                         GLsizeiptr(p.indexCount * kIndexBytes), indices.data());
    chunk.bytes += uint64_t(p.vertexCount) * kVertexBytes + uint64_t(p.indexCount) * kIndexBytes;
    chunk.parts.push_back(p);
  }
  if (texture) {
    const TextureLayer* color = texture->colourSource();
    const TextureLayer* normal = texture->find(TextureLayerKind::kNormal);
    assert(color && normal);
    chunk.textured = true;
    chunk.shaded = color->kind == TextureLayerKind::kShade;
    chunk.color = mTextures.upload(*color);
    chunk.normal = mTextures.upload(*normal);
    chunk.bytes +=
        mTextures.layerBytes(chunk.color.array) + mTextures.layerBytes(chunk.normal.array);
  }
  mResidentBytes += chunk.bytes;
  mChunks.emplace(node, std::move(chunk));
}

void GpuChunkStore::release(uint32_t node) {
  auto it = mChunks.find(node);
  if (it == mChunks.end()) return;
  for (const GpuChunkPart& p : it->second.parts) {
    if (p.vertexCount) mVertices.ranges.release(p.baseVertex, p.vertexCount);
    if (p.indexCount) mIndices.ranges.release(p.firstIndex, p.indexCount);
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

DrawnTexture drawnTexture(const ChunkTree& tree, const GpuChunkStore& store, uint32_t node) {
  const GpuChunk* chunk = store.find(node);
  if (!chunk) return {};
  const ChunkNode& n = tree.node(node);
  if (chunk->textured) return {chunk, n.level, 0, 0, 0};
  if (!n.inheritsTexture) return {};
  uint32_t depth = 0;
  for (uint32_t a = n.parent; a != kNoNode; a = tree.node(a).parent) {
    ++depth;
    const GpuChunk* c = store.find(a);
    if (!c) return {};
    if (!c->textured) continue;
    const ChunkNode& o = tree.node(a);
    const double side = double(tree.chunkCells(n.level));
    const auto& spacing = tree.spacing();
    return {c, o.level, depth,
            uint32_t(std::lround((n.box.min[0] - o.box.min[0]) / (side * spacing[0]))),
            uint32_t(std::lround((n.box.min[1] - o.box.min[1]) / (side * spacing[1])))};
  }
  return {};
}

}  // namespace terralod
