#include "terralod/format/texture_codec.h"

#include <algorithm>
#include <bit>

#include "terralod/format/byte_io.h"
#include "terralod/format/tileset_format.h"

namespace terralod {
namespace {

constexpr uint32_t kTextureMagic = 0x58544C54;  // "TLTX"
constexpr uint16_t kTextureBlobVersion = 1;
constexpr size_t kBlobHeaderBytes = 16;
constexpr size_t kLayerHeaderBytes = 16;
constexpr uint32_t kMaxLayers = 4;

uint32_t blockBytes(TextureEncoding e) {
  return e == TextureEncoding::kBc1 ? 8 : 16;
}

bool knownKind(uint8_t k) {
  return k == 1 || k == 2;
}
bool knownEncoding(uint8_t e) {
  return e == 1 || e == 2;
}

}  // namespace

uint32_t mipCount(uint32_t size) {
  return size == 0 ? 0 : uint32_t(std::bit_width(size));
}

uint64_t mipBytes(TextureEncoding encoding, uint32_t size, uint32_t m) {
  const uint64_t blocks = (mipSize(size, m) + 3) / 4;
  return blocks * blocks * blockBytes(encoding);
}

const TextureLayer* ChunkTexture::find(TextureLayerKind kind) const {
  for (const TextureLayer& l : layers)
    if (l.kind == kind) return &l;
  return nullptr;
}

uint64_t ChunkTexture::bytes() const {
  uint64_t total = 0;
  for (const TextureLayer& l : layers)
    for (const auto& m : l.mips) total += m.size();
  return total;
}

std::vector<uint8_t> encodeTexture(const ChunkTexture& texture) {
  size_t total = kBlobHeaderBytes + texture.layers.size() * kLayerHeaderBytes;
  for (const TextureLayer& l : texture.layers)
    for (const auto& m : l.mips) total += m.size();
  std::vector<uint8_t> out(total, 0);
  ByteWriter w(out.data());
  w.put<uint32_t>(kTextureMagic);
  w.put<uint16_t>(kTextureBlobVersion);
  w.put<uint16_t>(uint16_t(texture.layers.size()));
  w.seek(kBlobHeaderBytes);
  for (const TextureLayer& l : texture.layers) {
    uint32_t bytes = 0;
    for (const auto& m : l.mips) bytes += uint32_t(m.size());
    w.put<uint8_t>(uint8_t(l.kind));
    w.put<uint8_t>(uint8_t(l.encoding));
    w.put<uint8_t>(uint8_t(l.mips.size()));
    w.put<uint8_t>(l.flags);
    w.put<uint32_t>(l.size);
    w.put<uint32_t>(bytes);
    w.put<uint32_t>(0);
  }
  for (const TextureLayer& l : texture.layers)
    for (const auto& m : l.mips) w.putBytes(m.data(), m.size());
  ByteWriter crc(out.data());
  crc.seek(8);
  crc.put<uint32_t>(crc32Of(std::span(out).subspan(12)));
  return out;
}

Result<ChunkTexture> decodeTexture(std::span<const uint8_t> blob, const std::string& subject) {
  auto bad = [&](const std::string& what) {
    return makeError(subject, "invalid texture: " + what);
  };
  if (blob.size() < kBlobHeaderBytes) return bad("too short");
  ByteReader r(blob.data());
  if (r.get<uint32_t>() != kTextureMagic) return bad("wrong magic");
  if (r.get<uint16_t>() != kTextureBlobVersion) return bad("unknown texture blob version");
  const uint32_t layerCount = r.get<uint16_t>();
  const uint32_t crc = r.get<uint32_t>();
  if (crc != crc32Of(blob.subspan(12))) return bad("checksum mismatch");
  if (r.get<uint32_t>() != 0) return bad("reserved bytes are not zero");
  if (layerCount < 1 || layerCount > kMaxLayers) return bad("layer count");
  if (blob.size() < kBlobHeaderBytes + layerCount * kLayerHeaderBytes) return bad("too short");
  r.seek(kBlobHeaderBytes);
  ChunkTexture texture;
  uint64_t offset = kBlobHeaderBytes + layerCount * kLayerHeaderBytes;
  for (uint32_t i = 0; i < layerCount; ++i) {
    const uint8_t kind = r.get<uint8_t>(), encoding = r.get<uint8_t>();
    const uint32_t mips = r.get<uint8_t>();
    const uint8_t flags = r.get<uint8_t>();
    const uint32_t size = r.get<uint32_t>(), bytes = r.get<uint32_t>();
    const uint32_t reserved = r.get<uint32_t>();
    if (!knownKind(kind) || !knownEncoding(encoding)) return bad("unknown layer kind or encoding");
    // Version 1 pairs each kind with one encoding: colour BC1, normals BC5.
    if ((kind == uint8_t(TextureLayerKind::kColor)) != (encoding == uint8_t(TextureEncoding::kBc1)))
      return bad("layer kind and encoding do not match");
    if (reserved != 0) return bad("reserved bytes are not zero");
    if ((flags & ~kTextureSourceLimited) != 0) return bad("unknown layer flags");
    if (size < 2 || size > kMaxTextureSize) return bad("layer size");
    if (mips != mipCount(size)) return bad("mip count does not match the layer size");
    TextureLayer layer;
    layer.kind = TextureLayerKind(kind);
    layer.encoding = TextureEncoding(encoding);
    layer.flags = flags;
    layer.size = size;
    uint64_t expected = 0;
    for (uint32_t m = 0; m < mips; ++m) expected += mipBytes(layer.encoding, size, m);
    if (bytes != expected) return bad("layer byte count does not match its size");
    if (offset + bytes > blob.size()) return bad("layer data runs past the end");
    for (uint32_t m = 0; m < mips; ++m) {
      const uint64_t n = mipBytes(layer.encoding, size, m);
      layer.mips.emplace_back(blob.begin() + ptrdiff_t(offset),
                              blob.begin() + ptrdiff_t(offset + n));
      offset += n;
    }
    texture.layers.push_back(std::move(layer));
  }
  if (offset != blob.size()) return bad("trailing bytes");
  for (size_t i = 0; i < texture.layers.size(); ++i)
    for (size_t j = 0; j < i; ++j)
      if (texture.layers[i].kind == texture.layers[j].kind) return bad("duplicate layer");
  return texture;
}

}  // namespace terralod
