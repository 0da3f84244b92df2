#pragma once
// The GPU storage 4 × 4 VIPM chunks of one level share (a super-chunk's): their vertices in one
// set of growing buffers (positions, materials, splat weights, and each vertex's slot in the
// block), their normal maps and blot textures as layers of two array textures. A chunk draws
// alone from its range and layer; the block's chunks drawn as blots draw together in one call
// (VipmPass), with a 32-bit index list made from theirs. Render thread only.

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "gl_object.h"
#include "terralod/format/texture_codec.h"
#include "terralod/render/range_allocator.h"

namespace terralod {

class VipmGpuChunk;

/// Where a chunk's vertices are in its block's buffers (vertices).
struct VipmVertexRange {
  uint32_t first = 0;
  uint32_t count = 0;
};

class VipmBlock {
 public:
  static constexpr int kSide = 4;
  static constexpr int kSlots = kSide * kSide;

  /// A block whose chunks' normal maps are `normalSize` texels a side in `normalEncoding` with
  /// `normalLevels` mips (the blot textures: RGBA8, the same size, a full mip chain).
  VipmBlock(uint32_t normalSize, TextureEncoding normalEncoding, uint32_t normalLevels);
  VipmBlock(const VipmBlock&) = delete;
  VipmBlock& operator=(const VipmBlock&) = delete;

  /// Whether a chunk's textures fit the block's layers.
  bool fits(const TextureLayer& normals) const;

  /// Room for `count` vertices (the buffers grow, copying on the GPU), each tagged `slot`.
  VipmVertexRange allocate(uint32_t count, int slot);
  void release(VipmVertexRange range);

  /// Writes vertices [first, first + count) of `range`: positions (3 floats), materials (one
  /// byte), splat weights (8 bytes).
  void writePositions(VipmVertexRange range, uint32_t first,
                      std::span<const std::array<float, 3>> values);
  void writeMaterials(VipmVertexRange range, uint32_t first, std::span<const uint8_t> values);
  void writeWeights(VipmVertexRange range, uint32_t first,
                    std::span<const std::array<uint8_t, 8>> values);
  /// Stores a chunk's normal map (with its mips) and blot texture (level 0; mips are made) in
  /// layer `slot`.
  void writeTextures(int slot, const TextureLayer& normals, std::span<const uint8_t> blot);

  /// GPU memory of one layer: a normal map and a blot texture, with their mips.
  uint64_t layerBytes() const;
  /// GPU memory the block holds: its vertex buffers (with their spare room) and all its
  /// texture layers, used or not.
  uint64_t allocatedBytes() const;

  /// The chunk drawn from `slot` now (the latest uploaded there), or null.
  VipmGpuChunk* member(int slot) const { return mMembers[size_t(slot)]; }
  void setMember(int slot, VipmGpuChunk* chunk) { mMembers[size_t(slot)] = chunk; }
  bool empty() const;

  uint32_t positionBuffer() const { return mBuffers[0].id(); }
  uint32_t materialBuffer() const { return mBuffers[1].id(); }
  uint32_t weightBuffer() const { return mBuffers[2].id(); }
  uint32_t slotBuffer() const { return mBuffers[3].id(); }
  uint32_t normalArray() const { return mNormals.id(); }
  uint32_t blotArray() const { return mBlots.id(); }

  /// The index list of the chunks drawn together this frame (VipmPass): rebuilt only when
  /// `key` (which chunks, at which index versions) differs from the last one's.
  struct Batch {
    std::vector<uint64_t> key;
    std::vector<uint32_t> indices;  ///< surfaces first, then flanges
    uint32_t surfaceIndices = 0;
    GlBuffer buffer;
    uint32_t capacity = 0;  ///< indices the buffer holds
  };
  Batch& batch() { return mBatch; }

 private:
  void grow(uint32_t needed);
  // Values of buffer `buffer` (one per vertex) for vertices [first, first + size) of `range`.
  template <typename T>
  void write(size_t buffer, VipmVertexRange range, uint32_t first, std::span<const T> values);

  static constexpr std::array<uint32_t, 4> kUnit{12, 1, 8, 1};
  std::array<GlBuffer, 4> mBuffers;  // positions, materials, weights, slots
  RangeAllocator mRanges{0};
  GlTexture mNormals, mBlots;
  uint32_t mNormalSize = 0, mNormalLevels = 0, mBlotLevels = 0;
  TextureEncoding mNormalEncoding;
  std::array<VipmGpuChunk*, kSlots> mMembers{};
  Batch mBatch;
};

}  // namespace terralod
