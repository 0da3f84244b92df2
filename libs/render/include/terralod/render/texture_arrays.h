#pragma once
// Chunk textures on the GPU: 2D array textures per (encoding, size) class, a layer per chunk,
// the whole mip chain per layer. A frame's chunks whose layers share a pair of arrays draw in
// one multi-draw call with the arrays bound once.
//
// A class is a list of pages (array textures) that never move: when its pages are full a new
// page is made, twice the size of the last (up to kPageBytes or a single layer), and nothing is
// copied, so an upload never stalls a frame on a GPU copy of what is already resident. New
// layers go to the oldest page with room, so the newest pages empty first; an empty page is
// freed (unless it is its class's only one).
//
// With a GlWorker, pages are made ahead of need on the worker's context: when a class runs
// low (less than half its newest page free), the next page is requested, and reserve() says
// whether a layer can be had now without waiting for one. Without a worker, pages are made
// when needed. Render thread only (the worker only creates textures nobody uses yet).

#include <cstdint>
#include <map>
#include <utility>
#include <vector>

#include "terralod/format/texture_codec.h"
#include "terralod/render/gl_worker.h"

namespace terralod {

/// The GL internal format of chunk textures of `encoding` (colour as sRGB), and the sampling
/// every chunk texture uses (trilinear, clamped to the edge texels, which lie on the chunk
/// border): for kinds that keep chunk textures of their own (the VIPM kind's blocks).
uint32_t chunkTextureFormat(TextureEncoding encoding);
void setChunkTextureSampling(uint32_t texture);

struct TextureSlot {
  uint32_t array = 0;  ///< page index (arrayTexture(array) is its GL name)
  uint32_t layer = 0;
  uint32_t size = 0;  ///< texels per side
  uint8_t flags = 0;  ///< the layer's (kTextureSourceLimited)
};

class TextureArrays {
 public:
  /// The largest page made (a single layer may exceed it).
  static constexpr uint64_t kPageBytes = uint64_t{64} << 20;
  /// The first page of a class holds this many layers (if under kPageBytes).
  static constexpr uint32_t kFirstPageLayers = 8;

  TextureArrays() = default;
  ~TextureArrays();
  TextureArrays(const TextureArrays&) = delete;
  TextureArrays& operator=(const TextureArrays&) = delete;

  /// Makes pages ahead of need on `worker` from now on (nullptr: when needed, here).
  void setWorker(GlWorker* worker) { mWorker = worker; }
  /// Adopts pages the worker has finished. Call once a frame.
  void poll();
  /// Whether a layer of this class can be uploaded now without making a page here (always,
  /// without a worker). When not, a page is on its way.
  bool reserve(TextureEncoding encoding, uint32_t size);

  /// Copies one layer (all mips) into a free layer of its class (making a page here if there
  /// is none: reserve() first to avoid that).
  TextureSlot upload(const TextureLayer& layer);
  void release(const TextureSlot& slot);
  uint32_t arrayTexture(uint32_t array) const { return mPages[array].texture; }
  /// GPU bytes of one layer of the page's class.
  uint64_t layerBytes(uint32_t array) const { return mClasses[mPages[array].cls].layerBytes; }
  /// GPU bytes of every page, used layers or not.
  uint64_t allocatedBytes() const { return mAllocatedBytes; }
  /// Pages in use (for tests).
  size_t pageCount() const;

 private:
  struct Class {
    TextureEncoding encoding = TextureEncoding::kBc1;
    uint32_t size = 0, levels = 0;
    uint64_t layerBytes = 0;
    std::vector<uint32_t> pages;  ///< oldest first
    uint32_t freeLayers = 0;      ///< over its pages
    // A page being made on the worker: its job, and where the job puts the texture's name.
    std::shared_ptr<GlJob> pending;
    std::shared_ptr<uint32_t> pendingTexture;
    uint32_t pendingCapacity = 0;
  };
  struct Page {
    uint32_t cls = 0, texture = 0, capacity = 0;
    std::vector<uint32_t> freeLayers;
  };
  uint32_t classFor(TextureEncoding encoding, uint32_t size);
  uint32_t nextPageCapacity(uint32_t cls);
  uint32_t addPage(uint32_t cls, uint32_t texture, uint32_t capacity);
  void requestPage(uint32_t cls);
  void freePage(uint32_t page);

  std::vector<Class> mClasses;
  std::map<std::pair<TextureEncoding, uint32_t>, uint32_t> mClassIndex;
  std::vector<Page> mPages;  ///< freed pages keep their index with texture 0
  std::vector<uint32_t> mFreePageIds;
  uint64_t mAllocatedBytes = 0;
  int32_t mMaxLayers = 0;  ///< GL_MAX_ARRAY_TEXTURE_LAYERS, read on first use
  GlWorker* mWorker = nullptr;
};

}  // namespace terralod
