#include "terralod/format/texture_codec.h"

#include <algorithm>
#include <bit>
#include <memory>

#include <zstd.h>

#include "terralod/format/byte_io.h"
#include "terralod/format/tileset_format.h"

namespace terralod {
namespace {

constexpr uint32_t kTextureMagic = 0x58544C54;  // "TLTX"
constexpr uint16_t kRawBlobVersion = 1;
constexpr uint16_t kZstdBlobVersion = 2;
constexpr size_t kBlobHeaderBytes = 16;
constexpr size_t kLayerHeaderBytes = 16;
constexpr uint32_t kMaxLayers = 4;

uint32_t blockBytes(TextureEncoding e) {
  return e == TextureEncoding::kBc5 ? 16 : 8;
}

static_assert(uint8_t(TextureLayerKind::kColor) == uint8_t(TextureEncoding::kBc1) &&
              uint8_t(TextureLayerKind::kNormal) == uint8_t(TextureEncoding::kBc5) &&
              uint8_t(TextureLayerKind::kShade) == uint8_t(TextureEncoding::kBc4));

bool knownKind(uint8_t k) {
  return k >= 1 && k <= 3;
}
// Each kind has one encoding: colour BC1, normals BC5, shade BC4 (the enums' values match).
bool knownEncoding(uint8_t e) {
  return e >= 1 && e <= 3;
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

const TextureLayer* ChunkTexture::colourSource() const {
  const TextureLayer* colour = find(TextureLayerKind::kColor);
  return colour ? colour : find(TextureLayerKind::kShade);
}

uint64_t ChunkTexture::bytes() const {
  uint64_t total = 0;
  for (const TextureLayer& l : layers)
    for (const auto& m : l.mips) total += m.size();
  return total;
}

namespace {

// The blob header and the layer headers (the same in both versions; `bytes` is a layer's
// stored-as-is size), with `data` after them; the checksum covers everything from byte 12.
std::vector<uint8_t> assembleBlob(const ChunkTexture& texture, uint16_t version,
                                  std::span<const uint8_t> data) {
  const size_t headers = kBlobHeaderBytes + texture.layers.size() * kLayerHeaderBytes;
  std::vector<uint8_t> out(headers + data.size(), 0);
  ByteWriter w(out.data());
  w.put<uint32_t>(kTextureMagic);
  w.put<uint16_t>(version);
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
  w.putBytes(data.data(), data.size());
  ByteWriter crc(out.data());
  crc.seek(8);
  crc.put<uint32_t>(crc32Of(std::span(out).subspan(12)));
  return out;
}

std::vector<uint8_t> layerData(const ChunkTexture& texture) {
  std::vector<uint8_t> data;
  data.reserve(texture.bytes());
  for (const TextureLayer& l : texture.layers)
    for (const auto& m : l.mips) data.insert(data.end(), m.begin(), m.end());
  return data;
}

}  // namespace

std::vector<uint8_t> encodeTexture(const ChunkTexture& texture, int zstdLevel) {
  const std::vector<uint8_t> data = layerData(texture);
  std::vector<uint8_t> frame(ZSTD_compressBound(data.size()));
  const size_t n = ZSTD_compress(frame.data(), frame.size(), data.data(), data.size(), zstdLevel);
  // Only a level outside zstd's range fails, and the options refuse those.
  if (ZSTD_isError(n)) return {};
  return assembleBlob(texture, kZstdBlobVersion, std::span(frame).first(n));
}

std::vector<uint8_t> encodeRawTexture(const ChunkTexture& texture) {
  return assembleBlob(texture, kRawBlobVersion, layerData(texture));
}

Result<ChunkTexture> decodeTexture(std::span<const uint8_t> blob, const std::string& subject) {
  auto bad = [&](const std::string& what) {
    return makeError(subject, "invalid texture: " + what);
  };
  if (blob.size() < kBlobHeaderBytes) return bad("too short");
  ByteReader r(blob.data());
  if (r.get<uint32_t>() != kTextureMagic) return bad("wrong magic");
  const uint16_t version = r.get<uint16_t>();
  if (version != kRawBlobVersion && version != kZstdBlobVersion)
    return bad("unknown texture blob version");
  const uint32_t layerCount = r.get<uint16_t>();
  const uint32_t crc = r.get<uint32_t>();
  if (crc != crc32Of(blob.subspan(12))) return bad("checksum mismatch");
  if (r.get<uint32_t>() != 0) return bad("reserved bytes are not zero");
  if (layerCount < 1 || layerCount > kMaxLayers) return bad("layer count");
  if (blob.size() < kBlobHeaderBytes + layerCount * kLayerHeaderBytes) return bad("too short");
  r.seek(kBlobHeaderBytes);
  ChunkTexture texture;
  uint64_t total = 0;  // the layers' data, stored as it is (version 1) or compressed
  for (uint32_t i = 0; i < layerCount; ++i) {
    const uint8_t kind = r.get<uint8_t>(), encoding = r.get<uint8_t>();
    const uint32_t mips = r.get<uint8_t>();
    const uint8_t flags = r.get<uint8_t>();
    const uint32_t size = r.get<uint32_t>(), bytes = r.get<uint32_t>();
    const uint32_t reserved = r.get<uint32_t>();
    if (!knownKind(kind) || !knownEncoding(encoding)) return bad("unknown layer kind or encoding");
    if (kind != encoding) return bad("layer kind and encoding do not match");
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
    total += bytes;
    texture.layers.push_back(std::move(layer));
  }
  const std::span<const uint8_t> stored =
      blob.subspan(kBlobHeaderBytes + layerCount * kLayerHeaderBytes);
  std::span<const uint8_t> data = stored;
  std::unique_ptr<uint8_t[]> decompressed;
  if (version == kRawBlobVersion) {
    if (total > stored.size()) return bad("layer data runs past the end");
    if (total < stored.size()) return bad("trailing bytes");
  } else {
    // One zstd frame recording its content size, which the layer headers fix, and nothing
    // after it. The size is at most four 4097-texel layers' worth, so allocating it is safe.
    const unsigned long long size = ZSTD_getFrameContentSize(stored.data(), stored.size());
    if (size == ZSTD_CONTENTSIZE_ERROR || size == ZSTD_CONTENTSIZE_UNKNOWN)
      return bad("layer data is not a zstd frame with its size");
    if (size != total) return bad("layer data's size does not match the layer headers");
    const size_t frame = ZSTD_findFrameCompressedSize(stored.data(), stored.size());
    if (ZSTD_isError(frame)) return bad("layer data does not decompress");
    if (frame != stored.size()) return bad("trailing bytes");
    decompressed = std::make_unique_for_overwrite<uint8_t[]>(total);
    const size_t got = ZSTD_decompress(decompressed.get(), total, stored.data(), stored.size());
    if (ZSTD_isError(got) || got != total) return bad("layer data does not decompress");
    data = std::span<const uint8_t>(decompressed.get(), total);
  }
  size_t offset = 0;
  for (TextureLayer& layer : texture.layers)
    for (uint32_t m = 0; m < mipCount(layer.size); ++m) {
      const size_t n = mipBytes(layer.encoding, layer.size, m);
      layer.mips.emplace_back(data.begin() + ptrdiff_t(offset),
                              data.begin() + ptrdiff_t(offset + n));
      offset += n;
    }
  for (size_t i = 0; i < texture.layers.size(); ++i)
    for (size_t j = 0; j < i; ++j)
      if (texture.layers[i].kind == texture.layers[j].kind) return bad("duplicate layer");
  if (texture.find(TextureLayerKind::kColor) && texture.find(TextureLayerKind::kShade))
    return bad("both a colour and a shade layer");
  return texture;
}

}  // namespace terralod
