#pragma once
// Chunk geometry on the GPU. Every chunk lives in one shared vertex buffer and one shared
// 16-bit index buffer, so that a frame's chunks draw with a single multi-draw call; ranges are
// carved by first-fit allocators and the buffers grow (by copying on the GPU) when full.
// Textures go to per-size array textures (TextureArrays). Render thread only: create, use and
// destroy it where its GlContext is current.

#include <cstdint>
#include <unordered_map>
#include <vector>

#include "terralod/core/result.h"
#include "terralod/format/chunk_codec.h"
#include "terralod/format/texture_codec.h"
#include "terralod/render/gl_worker.h"
#include "terralod/render/range_allocator.h"
#include "terralod/render/texture_arrays.h"
#include "terralod/runtime/chunk_tree.h"

namespace terralod {

/// Where one part of a chunk is in the shared buffers (units: vertices and indices).
struct GpuChunkPart {
  uint32_t baseVertex = 0;
  uint32_t vertexCount = 0;
  uint32_t firstIndex = 0;
  uint32_t surfaceIndexCount = 0;  ///< surface indices first...
  uint32_t indexCount = 0;         ///< ...then skirt indices up to here
  /// Vertices from here on are skirt bottoms (vertexCount: none found), and the shallowest of
  /// them lies this many height steps below its top: the renderer slants skirts outwards by a
  /// fraction of that, so a skirt seen exactly edge-on still covers the crack it closes.
  uint32_t firstSkirtVertex = 0;
  uint32_t skirtDepthSteps = 0;
};

struct GpuChunk {
  double zBase = 0.0, zStep = 1.0;
  std::vector<GpuChunkPart> parts;
  bool textured = false;
  TextureSlot color, normal;  ///< when textured
  bool shaded = false;        ///< color holds a shade layer: the shader makes the colour
  uint64_t bytes = 0;         ///< GPU memory it takes (geometry and textures)
};

class GpuChunkStore {
 public:
  /// Makes empty buffers with room for about `initialBytes` of chunk data (they grow).
  explicit GpuChunkStore(uint64_t initialBytes = uint64_t{16} << 20);
  ~GpuChunkStore();
  GpuChunkStore(const GpuChunkStore&) = delete;
  GpuChunkStore& operator=(const GpuChunkStore&) = delete;

  /// Makes GPU memory ahead of need on `worker` from now on: texture pages (see
  /// TextureArrays) and, when a buffer is half full, its twice-as-large successor.
  void setWorker(GlWorker* worker);
  /// Adopts GPU memory the worker has made (a new buffer: what the old one holds is copied
  /// over). Call once a frame.
  void poll();
  /// Whether the chunk can be uploaded now without making GPU memory on this thread; when
  /// not, the memory is on its way (always true without a worker).
  bool reserve(const ChunkGeometry& geometry, const ChunkTexture* texture);

  /// Copies a decoded chunk to the GPU under `node` (replacing what was there). A texture
  /// must have a colour and a normal layer.
  void upload(uint32_t node, const ChunkGeometry& geometry, const ChunkTexture* texture = nullptr);
  /// Frees a chunk's GPU memory; nothing happens if it is not there.
  void release(uint32_t node);
  /// The chunk uploaded under `node`, or nullptr.
  const GpuChunk* find(uint32_t node) const;

  uint32_t vertexBuffer() const { return mVertices.name; }
  uint32_t indexBuffer() const { return mIndices.name; }
  const TextureArrays& textures() const { return mTextures; }
  /// GPU bytes held by chunks (not the buffers' spare room).
  uint64_t residentBytes() const { return mResidentBytes; }
  size_t chunkCount() const { return mChunks.size(); }

 private:
  // One growing buffer: its allocator, GL name and element size, and a successor being made.
  struct Buffer {
    Buffer(uint64_t capacity, size_t elementBytes) : ranges(capacity), unit(elementBytes) {}
    RangeAllocator ranges;
    size_t unit = 0;
    uint32_t name = 0;
    std::shared_ptr<GlJob> pending;
    std::shared_ptr<uint32_t> pendingName;
    uint64_t pendingCapacity = 0;
  };
  uint64_t allocate(Buffer& buffer, uint64_t count);
  void requestGrowth(Buffer& buffer);
  void adopt(Buffer& buffer, uint32_t bigger, uint64_t capacity);

  Buffer mVertices, mIndices;
  GlWorker* mWorker = nullptr;
  TextureArrays mTextures;
  std::unordered_map<uint32_t, GpuChunk> mChunks;
  uint64_t mResidentBytes = 0;
};

/// The texture a chunk draws: its own, or for one that inherits its texture
/// (kNodeInheritsTexture) its nearest textured ancestor's over the chunk's square, the
/// (column, row) of 2^depth a side from the owner's south-west corner. The resident set is
/// closed under parents, so a resident chunk's owner is resident. chunk null: none
/// (untextured, or the chunk is not resident).
struct DrawnTexture {
  const GpuChunk* chunk = nullptr;
  uint32_t level = 0;  ///< the owner's level: whose mip placements apply
  uint32_t depth = 0, column = 0, row = 0;
};
DrawnTexture drawnTexture(const ChunkTree& tree, const GpuChunkStore& store, uint32_t node);

}  // namespace terralod
