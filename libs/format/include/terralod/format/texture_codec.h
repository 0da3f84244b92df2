#pragma once
// Texture blobs (format versions 2 and 3): the colour and normal-map tiles of one chunk, each a
// square of GPU block-compressed texels with its whole mip chain, ready to upload once the
// zstd frame they are stored in (blob version 2) is undone.
// The blob sits right after the chunk's geometry blob, so one read fetches both.
//
// Texel placement is edge-aligned: texel i of a tile of `size` texels lies at i / (size - 1)
// of the chunk's side, so the outermost texels lie on the chunk's border and neighbours share
// them exactly (no seam under filtering). docs/format.md has the byte layout.

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "terralod/core/result.h"

namespace terralod {

enum class TextureLayerKind : uint8_t {
  kColor = 1,   ///< RGB, display (sRGB-encoded) values
  kNormal = 2,  ///< unit surface normal's x and y (east, north); z = sqrt(1 - x² - y²) >= 0
  /// Version 6: what the generated colour cannot get from the heights and normals a renderer
  /// already has: 0 water, else land at 0.5 + 0.5 (occlusion - 0.6) / 0.4 (generated_colour.h).
  /// A chunk has a colour layer or a shade layer, never both.
  kShade = 3,
};

enum class TextureEncoding : uint8_t {
  kBc1 = 1,  ///< BC1 / DXT1 RGB, 8 bytes per 4x4 block
  kBc5 = 2,  ///< BC5 / RGTC2 two channels, unsigned, 16 bytes per block; v = (c + 1) / 2
  kBc4 = 3,  ///< BC4 / RGTC1 one channel, unsigned, 8 bytes per block (version 6)
};

/// Layer flag: the tile's texels are the source's own resolution, coarser than the
/// eq. 7 size for the tileset's τ (the source had no more detail to give).
inline constexpr uint8_t kTextureSourceLimited = 1u;

inline constexpr uint32_t kMaxTextureSize = 4097;

struct TextureLayer {
  TextureLayerKind kind = TextureLayerKind::kColor;
  TextureEncoding encoding = TextureEncoding::kBc1;
  uint8_t flags = 0;
  uint32_t size = 0;                       ///< texels per side, 2 .. kMaxTextureSize
  std::vector<std::vector<uint8_t>> mips;  ///< level 0 first; level m is max(1, size >> m)
  bool sourceLimited() const { return (flags & kTextureSourceLimited) != 0; }
};

struct ChunkTexture {
  std::vector<TextureLayer> layers;
  const TextureLayer* find(TextureLayerKind kind) const;
  /// The layer the chunk's colour comes from: its colour layer, else its shade layer.
  const TextureLayer* colourSource() const;
  uint64_t bytes() const;  ///< texel data over all layers and mips
};

/// Mip levels of a full chain for a square of `size` texels (1 + floor(log2(size))).
uint32_t mipCount(uint32_t size);
/// Side of mip level `m`.
inline uint32_t mipSize(uint32_t size, uint32_t m) {
  return std::max(1u, size >> m);
}
/// Bytes of one mip level of `size`-texel tile (whole 4x4 blocks).
uint64_t mipBytes(TextureEncoding encoding, uint32_t size, uint32_t m);

/// A texture blob of version 2 (format version 3): the layers' blocks in one zstd frame at
/// `zstdLevel`, so uniform areas (sea, flats, the padding around the data) cost next to
/// nothing. Static tilesets write these.
std::vector<uint8_t> encodeTexture(const ChunkTexture& texture, int zstdLevel);
/// A texture blob of version 1 (format version 2): the blocks as they are. VIPM tilesets
/// write these (their normal maps are small, and their tilesets stay version 2).
std::vector<uint8_t> encodeRawTexture(const ChunkTexture& texture);
/// Decodes and validates a texture blob of either version (never trusts it); `subject` names
/// it in errors.
Result<ChunkTexture> decodeTexture(std::span<const uint8_t> blob, const std::string& subject);

}  // namespace terralod
