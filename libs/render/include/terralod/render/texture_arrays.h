#pragma once
// Chunk textures on the GPU: one 2D array texture per (encoding, size) class, a layer per
// chunk, the whole mip chain per layer. A frame's chunks of one class pair draw in one
// multi-draw call with the arrays bound once. Arrays grow (by copying on the GPU) when full.
// Render thread only.

#include <cstdint>
#include <map>
#include <utility>
#include <vector>

#include "terralod/format/texture_codec.h"

namespace terralod {

struct TextureSlot {
  uint32_t array = 0;  ///< class index (arrayTexture(array) is its GL name)
  uint32_t layer = 0;
  uint32_t size = 0;  ///< texels per side
  uint8_t flags = 0;  ///< the layer's (kTextureSourceLimited)
};

class TextureArrays {
 public:
  TextureArrays() = default;
  ~TextureArrays();
  TextureArrays(const TextureArrays&) = delete;
  TextureArrays& operator=(const TextureArrays&) = delete;

  /// Copies one layer (all mips) into a free layer of its class.
  TextureSlot upload(const TextureLayer& layer);
  void release(const TextureSlot& slot);
  uint32_t arrayTexture(uint32_t array) const { return mArrays[array].texture; }
  /// GPU bytes of one layer of a class.
  uint64_t layerBytes(uint32_t array) const { return mArrays[array].layerBytes; }

 private:
  struct Array {
    TextureEncoding encoding = TextureEncoding::kBc1;
    uint32_t size = 0, levels = 0, capacity = 0;
    uint32_t texture = 0;
    uint64_t layerBytes = 0;
    std::vector<uint32_t> freeLayers;
  };
  uint32_t classFor(TextureEncoding encoding, uint32_t size);
  void grow(Array& a);

  std::vector<Array> mArrays;
  std::map<std::pair<TextureEncoding, uint32_t>, uint32_t> mClasses;
};

}  // namespace terralod
