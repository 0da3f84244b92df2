#include "terralod/format/texture_codec.h"
#include "terralod/format/vipm_chunk_codec.h"

#include <gtest/gtest.h>

#include <cstring>
#include <random>

#include <zstd.h>

#include "terralod/format/tileset_format.h"

namespace terralod {
namespace {

// Blob layout (texture_codec.cpp): a 16-byte header (magic, version, layer count, CRC-32 of
// bytes [12, end), reserved), one 16-byte header per layer (kind, encoding, mips, flags,
// size, bytes, reserved), then every layer's mips in order: as they are (version 1,
// encodeRawTexture) or in one zstd frame (version 2, encodeTexture).
constexpr size_t kHeader = 16, kLayerHeader = 16;

TextureLayer makeLayer(TextureLayerKind kind, TextureEncoding encoding, uint32_t size,
                       uint8_t flags, uint32_t seed) {
  std::mt19937 rng(seed);
  TextureLayer l;
  l.kind = kind;
  l.encoding = encoding;
  l.flags = flags;
  l.size = size;
  for (uint32_t m = 0; m < mipCount(size); ++m) {
    std::vector<uint8_t> bytes(mipBytes(encoding, size, m));
    for (uint8_t& b : bytes) b = uint8_t(rng());
    l.mips.push_back(std::move(bytes));
  }
  return l;
}

ChunkTexture makeTexture() {
  ChunkTexture t;
  t.layers.push_back(makeLayer(TextureLayerKind::kColor, TextureEncoding::kBc1, 65, 0, 1));
  t.layers.push_back(
      makeLayer(TextureLayerKind::kNormal, TextureEncoding::kBc5, 33, kTextureSourceLimited, 2));
  return t;
}

// Recomputes the header's checksum after an edit, so that the check under test fires rather
// than the checksum's.
void fixCrc(std::vector<uint8_t>& blob) {
  const uint32_t crc = crc32Of(std::span<const uint8_t>(blob).subspan(12));
  for (int i = 0; i < 4; ++i) blob[8 + size_t(i)] = uint8_t(crc >> (8 * i));
}

std::string decodeError(const std::vector<uint8_t>& blob) {
  auto r = decodeTexture(blob, "chunk 3/1/2");
  if (r.ok()) return "(decoded without error)";
  return r.error().message;
}

TEST(TextureCodec, MipCountAndBytes) {
  EXPECT_EQ(mipCount(0), 0u);
  EXPECT_EQ(mipCount(1), 1u);
  EXPECT_EQ(mipCount(2), 2u);
  EXPECT_EQ(mipCount(5), 3u);   // 5, 2, 1
  EXPECT_EQ(mipCount(33), 6u);  // 33, 16, 8, 4, 2, 1
  EXPECT_EQ(mipCount(65), 7u);  // 65, 32, 16, 8, 4, 2, 1
  EXPECT_EQ(mipCount(kMaxTextureSize), 13u);
  EXPECT_EQ(mipSize(65, 0), 65u);
  EXPECT_EQ(mipSize(65, 1), 32u);
  EXPECT_EQ(mipSize(65, 6), 1u);
  EXPECT_EQ(mipSize(65, 9), 1u);
  EXPECT_EQ(mipBytes(TextureEncoding::kBc1, 65, 0), 17u * 17u * 8u);
  EXPECT_EQ(mipBytes(TextureEncoding::kBc1, 65, 1), 8u * 8u * 8u);
  EXPECT_EQ(mipBytes(TextureEncoding::kBc1, 65, 4), 8u);  // 4x4: one block
  EXPECT_EQ(mipBytes(TextureEncoding::kBc1, 65, 5), 8u);  // 2x2: still one whole block
  EXPECT_EQ(mipBytes(TextureEncoding::kBc1, 65, 6), 8u);  // 1x1
  EXPECT_EQ(mipBytes(TextureEncoding::kBc5, 33, 0), 9u * 9u * 16u);
  EXPECT_EQ(mipBytes(TextureEncoding::kBc5, 33, 1), 4u * 4u * 16u);
  EXPECT_EQ(mipBytes(TextureEncoding::kBc5, 33, 5), 16u);
}

TEST(TextureCodec, TwoLayerRoundTrip) {
  const ChunkTexture t = makeTexture();
  const std::vector<uint8_t> blob = encodeRawTexture(t);
  uint64_t data = 0;
  for (const TextureLayer& l : t.layers)
    for (uint32_t m = 0; m < mipCount(l.size); ++m) data += mipBytes(l.encoding, l.size, m);
  EXPECT_EQ(t.bytes(), data);
  EXPECT_EQ(blob.size(), kHeader + 2 * kLayerHeader + data);
  EXPECT_EQ(std::string(blob.begin(), blob.begin() + 4), "TLTX");

  auto r = decodeTexture(blob, "test");
  ASSERT_TRUE(r.ok()) << r.error().message;
  ASSERT_EQ(r->layers.size(), 2u);
  EXPECT_EQ(r->bytes(), data);
  for (size_t i = 0; i < 2; ++i) {
    const TextureLayer &a = r->layers[i], &b = t.layers[i];
    EXPECT_EQ(a.kind, b.kind);
    EXPECT_EQ(a.encoding, b.encoding);
    EXPECT_EQ(a.flags, b.flags);
    EXPECT_EQ(a.size, b.size);
    ASSERT_EQ(a.mips.size(), mipCount(b.size));
    for (uint32_t m = 0; m < a.mips.size(); ++m) {
      EXPECT_EQ(a.mips[m].size(), mipBytes(b.encoding, b.size, m)) << "layer " << i << " mip " << m;
      EXPECT_EQ(a.mips[m], b.mips[m]) << "layer " << i << " mip " << m;
    }
  }
  EXPECT_FALSE(r->layers[0].sourceLimited());
  EXPECT_TRUE(r->layers[1].sourceLimited());
  ASSERT_NE(r->find(TextureLayerKind::kNormal), nullptr);
  EXPECT_EQ(r->find(TextureLayerKind::kNormal)->size, 33u);
  EXPECT_EQ(r->find(TextureLayerKind::kColor)->size, 65u);

  // The edit helper itself: rewriting the checksum of an unedited blob changes nothing.
  std::vector<uint8_t> same = blob;
  fixCrc(same);
  EXPECT_EQ(same, blob);
}

TEST(TextureCodec, SingleLayerRoundTrip) {
  ChunkTexture t;
  t.layers.push_back(makeLayer(TextureLayerKind::kNormal, TextureEncoding::kBc5, 2, 0, 7));
  auto r = decodeTexture(encodeRawTexture(t), "test");
  ASSERT_TRUE(r.ok()) << r.error().message;
  ASSERT_EQ(r->layers.size(), 1u);
  EXPECT_EQ(r->layers[0].mips, t.layers[0].mips);
  EXPECT_EQ(r->find(TextureLayerKind::kColor), nullptr);
}

TEST(TextureCodec, RejectsWrongMagic) {
  std::vector<uint8_t> blob = encodeRawTexture(makeTexture());
  blob[0] ^= 0x01;
  EXPECT_EQ(decodeError(blob), "chunk 3/1/2: invalid texture: wrong magic");
}

TEST(TextureCodec, RejectsFlippedDataByte) {
  const std::vector<uint8_t> good = encodeRawTexture(makeTexture());
  for (size_t at :
       {size_t(12), kHeader + 4, kHeader + 2 * kLayerHeader, good.size() / 2, good.size() - 1}) {
    std::vector<uint8_t> blob = good;
    blob[at] ^= 0x10;
    EXPECT_EQ(decodeError(blob), "chunk 3/1/2: invalid texture: checksum mismatch") << at;
  }
}

TEST(TextureCodec, RejectsTruncatedBlob) {
  const std::vector<uint8_t> good = encodeRawTexture(makeTexture());
  // Shorter than the header.
  EXPECT_EQ(decodeError(std::vector<uint8_t>(good.begin(), good.begin() + 10)),
            "chunk 3/1/2: invalid texture: too short");
  EXPECT_EQ(decodeError({}), "chunk 3/1/2: invalid texture: too short");
  // One byte short: the checksum, which covers the data, no longer matches.
  std::vector<uint8_t> blob(good.begin(), good.end() - 1);
  EXPECT_EQ(decodeError(blob), "chunk 3/1/2: invalid texture: checksum mismatch");
  // One byte short with a checksum that matches what is left: the layer sizes catch it.
  fixCrc(blob);
  EXPECT_EQ(decodeError(blob), "chunk 3/1/2: invalid texture: layer data runs past the end");
  // Cut inside the layer headers.
  blob.assign(good.begin(), good.begin() + kHeader + kLayerHeader + 3);
  fixCrc(blob);
  EXPECT_EQ(decodeError(blob), "chunk 3/1/2: invalid texture: too short");
  // And a byte too many.
  blob = good;
  blob.push_back(0);
  fixCrc(blob);
  EXPECT_EQ(decodeError(blob), "chunk 3/1/2: invalid texture: trailing bytes");
}

TEST(TextureCodec, RejectsUnknownEncoding) {
  std::vector<uint8_t> blob = encodeRawTexture(makeTexture());
  blob[kHeader + kLayerHeader + 1] = 4;  // second layer's encoding
  fixCrc(blob);
  EXPECT_EQ(decodeError(blob), "chunk 3/1/2: invalid texture: unknown layer kind or encoding");
  blob[kHeader + kLayerHeader + 1] = 0;
  fixCrc(blob);
  EXPECT_EQ(decodeError(blob), "chunk 3/1/2: invalid texture: unknown layer kind or encoding");
  blob = encodeRawTexture(makeTexture());
  blob[kHeader] = 4;  // first layer's kind
  fixCrc(blob);
  EXPECT_EQ(decodeError(blob), "chunk 3/1/2: invalid texture: unknown layer kind or encoding");
}

TEST(TextureCodec, RejectsInconsistentMipCount) {
  for (uint8_t mips : {uint8_t(6), uint8_t(8), uint8_t(0)}) {
    std::vector<uint8_t> blob = encodeRawTexture(makeTexture());
    blob[kHeader + 2] = mips;  // the 65-texel layer has 7
    fixCrc(blob);
    EXPECT_EQ(decodeError(blob),
              "chunk 3/1/2: invalid texture: mip count does not match the layer size")
        << int(mips);
  }
  // A layer that left out its last mip is caught when encoded as it is.
  ChunkTexture t = makeTexture();
  t.layers[1].mips.pop_back();
  EXPECT_EQ(decodeError(encodeRawTexture(t)),
            "chunk 3/1/2: invalid texture: mip count does not match the layer size");
}

TEST(TextureCodec, RejectsDuplicateLayerKind) {
  ChunkTexture t = makeTexture();
  t.layers[1] = makeLayer(TextureLayerKind::kColor, TextureEncoding::kBc1, 33, 0, 3);
  EXPECT_EQ(decodeError(encodeRawTexture(t)), "chunk 3/1/2: invalid texture: duplicate layer");
  // Editing a valid blob's second kind (BC5) to colour pairs colour with the wrong encoding.
  std::vector<uint8_t> blob = encodeRawTexture(makeTexture());
  blob[kHeader + kLayerHeader] = uint8_t(TextureLayerKind::kColor);
  fixCrc(blob);
  EXPECT_EQ(decodeError(blob),
            "chunk 3/1/2: invalid texture: layer kind and encoding do not match");
}

TEST(TextureCodec, RejectsNonZeroReservedBytes) {
  std::vector<uint8_t> blob = encodeRawTexture(makeTexture());
  blob[12] = 1;  // the blob header's reserved word
  fixCrc(blob);
  EXPECT_EQ(decodeError(blob), "chunk 3/1/2: invalid texture: reserved bytes are not zero");
  blob = encodeRawTexture(makeTexture());
  blob[kHeader + 12] = 1;  // the first layer header's
  fixCrc(blob);
  EXPECT_EQ(decodeError(blob), "chunk 3/1/2: invalid texture: reserved bytes are not zero");
}

TEST(TextureCodec, RejectsOtherHeaderDamage) {
  const std::vector<uint8_t> good = encodeRawTexture(makeTexture());
  auto edited = [&](size_t at, uint8_t value) {
    std::vector<uint8_t> b = good;
    b[at] = value;
    fixCrc(b);
    return decodeError(b);
  };
  // The version (bytes 4-5) is outside the checksum.
  EXPECT_EQ(edited(4, 3), "chunk 3/1/2: invalid texture: unknown texture blob version");
  EXPECT_EQ(edited(4, 0), "chunk 3/1/2: invalid texture: unknown texture blob version");
  // Version 2 keeps its blocks in a zstd frame, which raw blocks are not.
  EXPECT_EQ(edited(4, 2),
            "chunk 3/1/2: invalid texture: layer data is not a zstd frame with its size");
  EXPECT_EQ(edited(6, 0), "chunk 3/1/2: invalid texture: layer count");
  EXPECT_EQ(edited(6, 5), "chunk 3/1/2: invalid texture: layer count");
  EXPECT_EQ(edited(kHeader + 3, 2), "chunk 3/1/2: invalid texture: unknown layer flags");
  EXPECT_EQ(edited(kHeader + 4, 1), "chunk 3/1/2: invalid texture: layer size");  // size 1
  EXPECT_EQ(edited(kHeader + 8, 0),
            "chunk 3/1/2: invalid texture: layer byte count does not match its size");
}

uint16_t blobVersion(const std::vector<uint8_t>& blob) {
  return uint16_t(blob[4] | blob[5] << 8);
}

TEST(TextureCodec, CompressedRoundTrip) {
  const ChunkTexture t = makeTexture();
  const std::vector<uint8_t> blob = encodeTexture(t, 3);
  EXPECT_EQ(std::string(blob.begin(), blob.begin() + 4), "TLTX");
  EXPECT_EQ(blobVersion(blob), 2u);
  EXPECT_EQ(blobVersion(encodeRawTexture(t)), 1u);
  auto r = decodeTexture(blob, "test");
  ASSERT_TRUE(r.ok()) << r.error().message;
  ASSERT_EQ(r->layers.size(), 2u);
  for (size_t i = 0; i < 2; ++i) {
    EXPECT_EQ(r->layers[i].kind, t.layers[i].kind);
    EXPECT_EQ(r->layers[i].flags, t.layers[i].flags);
    EXPECT_EQ(r->layers[i].size, t.layers[i].size);
    EXPECT_EQ(r->layers[i].mips, t.layers[i].mips) << "layer " << i;
  }
  // The layer headers are the same in both versions; only the data after them differs.
  const std::vector<uint8_t> raw = encodeRawTexture(t);
  EXPECT_TRUE(std::equal(blob.begin() + 16, blob.begin() + 48, raw.begin() + 16));
}

// Sea, flats and the padding around the data give runs of identical blocks: they must cost
// next to nothing, where random blocks cost what they are.
TEST(TextureCodec, UniformLayersCostNextToNothing) {
  ChunkTexture uniform;
  uniform.layers.push_back(makeLayer(TextureLayerKind::kNormal, TextureEncoding::kBc5, 1025, 1, 0));
  for (auto& mip : uniform.layers[0].mips)
    for (size_t i = 0; i < mip.size(); ++i) mip[i] = uint8_t(i % 16 < 2 ? 0x80 : 0);
  const uint64_t raw = uniform.bytes();
  const std::vector<uint8_t> blob = encodeTexture(uniform, 3);
  EXPECT_LT(blob.size() * 100, raw) << blob.size() << " bytes for " << raw;
  ASSERT_TRUE(decodeTexture(blob, "test").ok());
  EXPECT_EQ(decodeTexture(blob, "test")->layers[0].mips, uniform.layers[0].mips);
  const ChunkTexture noisy = makeTexture();
  EXPECT_GT(encodeTexture(noisy, 3).size(), noisy.bytes());  // incompressible: a little more
}

TEST(TextureCodec, RejectsADamagedFrame) {
  const ChunkTexture t = makeTexture();
  const std::vector<uint8_t> good = encodeTexture(t, 3);
  const size_t frameAt = kHeader + 2 * kLayerHeader;
  // Any flipped byte: the checksum.
  for (size_t at : {frameAt, frameAt + 7, good.size() / 2, good.size() - 1}) {
    std::vector<uint8_t> blob = good;
    blob[at] ^= 0x10;
    EXPECT_EQ(decodeError(blob), "chunk 3/1/2: invalid texture: checksum mismatch") << at;
  }
  // With the checksum made to match: cut short, a byte too many, not a frame at all.
  std::vector<uint8_t> blob(good.begin(), good.end() - 1);
  fixCrc(blob);
  EXPECT_EQ(decodeError(blob), "chunk 3/1/2: invalid texture: layer data does not decompress");
  blob = good;
  blob.push_back(0);
  fixCrc(blob);
  EXPECT_EQ(decodeError(blob), "chunk 3/1/2: invalid texture: trailing bytes");
  blob.assign(good.begin(), good.begin() + ptrdiff_t(frameAt));
  fixCrc(blob);
  EXPECT_EQ(decodeError(blob),
            "chunk 3/1/2: invalid texture: layer data is not a zstd frame with its size");
  // A frame of another size than the layer headers say (a whole frame, 16 bytes short).
  std::vector<uint8_t> data;
  for (const TextureLayer& l : t.layers)
    for (const auto& m : l.mips) data.insert(data.end(), m.begin(), m.end());
  data.resize(data.size() - 16);
  std::vector<uint8_t> frame(ZSTD_compressBound(data.size()));
  frame.resize(ZSTD_compress(frame.data(), frame.size(), data.data(), data.size(), 3));
  blob.assign(good.begin(), good.begin() + ptrdiff_t(frameAt));
  blob.insert(blob.end(), frame.begin(), frame.end());
  fixCrc(blob);
  EXPECT_EQ(decodeError(blob),
            "chunk 3/1/2: invalid texture: layer data's size does not match the layer headers");
}

TEST(VipmNormalMapLayer, OneBc5NormalLayerOfTheChunksGridPointsIsAccepted) {
  ChunkTexture t;
  t.layers.push_back(makeLayer(TextureLayerKind::kNormal, TextureEncoding::kBc5, 65, 1, 3));
  auto leaf = decodeVipmNormalMap(encodeRawTexture(t), 64, "v.tlod chunk 5");
  ASSERT_TRUE(leaf.ok()) << leaf.error().message;
  EXPECT_EQ(leaf->size, 65u);
  EXPECT_EQ(leaf->mips, t.layers[0].mips);
  const std::string wrong =
      "v.tlod chunk 5: invalid texture: a VIPM chunk's texture must be one BC5 normal layer of "
      "129 texels";
  EXPECT_EQ(decodeVipmNormalMap(encodeRawTexture(t), 128, "v.tlod chunk 5").error().message, wrong);
  // A colour layer too, a colour layer alone, a normal layer in BC1: refused.
  ChunkTexture root;
  root.layers.push_back(makeLayer(TextureLayerKind::kNormal, TextureEncoding::kBc5, 129, 1, 4));
  ASSERT_TRUE(decodeVipmNormalMap(encodeRawTexture(root), 128, "v.tlod chunk 5").ok());
  ChunkTexture both = root;
  both.layers.push_back(makeLayer(TextureLayerKind::kColor, TextureEncoding::kBc1, 129, 0, 5));
  EXPECT_EQ(decodeVipmNormalMap(encodeRawTexture(both), 128, "v.tlod chunk 5").error().message,
            wrong);
  ChunkTexture colour;
  colour.layers.push_back(makeLayer(TextureLayerKind::kColor, TextureEncoding::kBc1, 129, 0, 6));
  EXPECT_FALSE(decodeVipmNormalMap(encodeRawTexture(colour), 128, "v.tlod chunk 5").ok());
  ChunkTexture bc1;
  bc1.layers.push_back(makeLayer(TextureLayerKind::kNormal, TextureEncoding::kBc1, 129, 0, 7));
  EXPECT_FALSE(decodeVipmNormalMap(encodeRawTexture(bc1), 128, "v.tlod chunk 5").ok());
  // Missing or damaged.
  EXPECT_EQ(decodeVipmNormalMap({}, 128, "v.tlod chunk 5").error().message,
            "v.tlod chunk 5: invalid texture: a VIPM chunk has no normal map");
  std::vector<uint8_t> damaged = encodeRawTexture(root);
  damaged[100] ^= 1;
  EXPECT_EQ(decodeVipmNormalMap(damaged, 128, "v.tlod chunk 5").error().message,
            "v.tlod chunk 5: invalid texture: checksum mismatch");
}

// Version 6: a shade layer (BC4) in place of the colour; never both, never in another encoding.
TEST(TextureCodec, ShadeLayerRoundTripsAndStandsAlone) {
  ChunkTexture t;
  t.layers.push_back(makeLayer(TextureLayerKind::kShade, TextureEncoding::kBc4, 33, 0, 8));
  t.layers.push_back(makeLayer(TextureLayerKind::kNormal, TextureEncoding::kBc5, 65, 0, 9));
  EXPECT_EQ(mipBytes(TextureEncoding::kBc4, 33, 0), 9u * 9u * 8u);
  auto r = decodeTexture(encodeTexture(t, 3), "chunk 3/1/2");
  ASSERT_TRUE(r.ok()) << r.error().message;
  ASSERT_NE(r->colourSource(), nullptr);
  EXPECT_EQ(r->colourSource()->kind, TextureLayerKind::kShade);
  EXPECT_EQ(r->colourSource()->mips, t.layers[0].mips);
  ChunkTexture both = t;
  both.layers.push_back(makeLayer(TextureLayerKind::kColor, TextureEncoding::kBc1, 33, 0, 10));
  EXPECT_EQ(decodeError(encodeTexture(both, 3)),
            "chunk 3/1/2: invalid texture: both a colour and a shade layer");
  ChunkTexture wrong;
  wrong.layers.push_back(makeLayer(TextureLayerKind::kShade, TextureEncoding::kBc1, 33, 0, 11));
  EXPECT_EQ(decodeError(encodeTexture(wrong, 3)),
            "chunk 3/1/2: invalid texture: layer kind and encoding do not match");
  // A colour layer is the colour source where there is one.
  EXPECT_EQ(makeTexture().colourSource()->kind, TextureLayerKind::kColor);
}

}  // namespace
}  // namespace terralod
