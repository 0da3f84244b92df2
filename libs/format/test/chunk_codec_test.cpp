#include "terralod/format/chunk_codec.h"

#include <gtest/gtest.h>
#include <sys/resource.h>
#include <zstd.h>

#include <algorithm>
#include <array>
#include <cstring>
#include <random>

namespace terralod {
namespace {

// A grid-like chunk: (n+1)^2 vertices, two triangles per cell, plus a skirt along one side.
ChunkGeometry makeGeometry(int n, uint32_t seed) {
  std::mt19937 rng(seed);
  ChunkGeometry g;
  g.zBase = 1234.5;
  g.zStep = 0.015625;
  ChunkPart& p = g.parts.emplace_back();
  for (int y = 0; y <= n; ++y)
    for (int x = 0; x <= n; ++x)
      p.vertices.push_back({uint16_t(x * 3), uint16_t(y * 3), uint16_t(30000 + rng() % 2000),
                            int16_t(int(rng() % 401) - 200)});
  auto at = [n](int x, int y) { return uint32_t(y * (n + 1) + x); };
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x)
      p.indices.insert(p.indices.end(), {at(x, y), at(x + 1, y), at(x + 1, y + 1), at(x, y),
                                         at(x + 1, y + 1), at(x, y + 1)});
  p.surfaceIndexCount = uint32_t(p.indices.size());
  const uint32_t first = uint32_t(p.vertices.size());
  for (int x = 0; x <= n; ++x) {
    ChunkVertex bottom = p.vertices[at(x, 0)];
    bottom.z -= 500;
    p.vertices.push_back(bottom);
  }
  for (int x = 0; x < n; ++x)
    p.indices.insert(p.indices.end(),
                     {at(x, 0), first + x, first + x + 1, at(x, 0), first + x + 1, at(x + 1, 0)});
  return g;
}

// Triangles as rotation-normalised vertex triples (the index codec may rotate a triangle).
std::vector<std::array<ChunkVertex, 3>> triangles(const ChunkPart& p, size_t from, size_t to) {
  std::vector<std::array<ChunkVertex, 3>> out;
  for (size_t k = from; k < to; k += 3) {
    std::array<uint32_t, 3> t = {p.indices[k], p.indices[k + 1], p.indices[k + 2]};
    std::array<ChunkVertex, 3> v;
    auto key = [&](uint32_t i) {
      const ChunkVertex& c = p.vertices[i];
      return std::tuple(c.x, c.y, c.z, c.morphDelta);
    };
    const int first =
        int(std::min_element(t.begin(), t.end(),
                             [&](uint32_t a, uint32_t b) { return key(a) < key(b); }) -
            t.begin());
    for (int j = 0; j < 3; ++j) v[j] = p.vertices[t[(first + j) % 3]];
    out.push_back(v);
  }
  auto less = [](const std::array<ChunkVertex, 3>& a, const std::array<ChunkVertex, 3>& b) {
    auto k = [](const ChunkVertex& c) { return std::tuple(c.x, c.y, c.z, c.morphDelta); };
    return std::tuple(k(a[0]), k(a[1]), k(a[2])) < std::tuple(k(b[0]), k(b[1]), k(b[2]));
  };
  std::sort(out.begin(), out.end(), less);
  return out;
}

TEST(ChunkCodec, RoundTripPreservesEveryTriangle) {
  ChunkGeometry g = makeGeometry(40, 1);
  const ChunkGeometry original = g;
  optimizeChunkPart(g.parts[0]);
  const std::vector<uint8_t> blob = encodeChunk(g);
  auto decoded = decodeChunk(blob, "test");
  ASSERT_TRUE(decoded.ok()) << decoded.error().message;
  EXPECT_EQ(decoded->zBase, g.zBase);
  EXPECT_EQ(decoded->zStep, g.zStep);
  ASSERT_EQ(decoded->parts.size(), 1u);
  const ChunkPart& p = decoded->parts[0];
  EXPECT_EQ(p.vertices, g.parts[0].vertices);
  EXPECT_EQ(p.surfaceIndexCount, original.parts[0].surfaceIndexCount);
  const ChunkPart& o = original.parts[0];
  EXPECT_EQ(triangles(p, 0, p.surfaceIndexCount), triangles(o, 0, o.surfaceIndexCount));
  EXPECT_EQ(triangles(p, p.surfaceIndexCount, p.indices.size()),
            triangles(o, o.surfaceIndexCount, o.indices.size()));
  // The codecs earn their keep: well under the raw 8 bytes per vertex + 12 per triangle.
  const size_t raw = o.vertices.size() * 8 + o.indices.size() * 4;
  EXPECT_LT(blob.size(), raw / 3);
}

TEST(ChunkCodec, SeveralPartsRoundTrip) {
  ChunkGeometry g = makeGeometry(10, 2);
  g.parts.push_back(makeGeometry(5, 3).parts[0]);
  auto decoded = decodeChunk(encodeChunk(g, 3), "test");
  ASSERT_TRUE(decoded.ok());
  ASSERT_EQ(decoded->parts.size(), 2u);
  EXPECT_EQ(decoded->parts[1].vertices, g.parts[1].vertices);
}

// Every prefix and many bit flips of a valid blob decode to an error or to valid geometry,
// never to a crash or an out-of-range index.
TEST(ChunkCodec, CorruptBlobsNeverCrash) {
  const std::vector<uint8_t> blob = encodeChunk(makeGeometry(20, 4));
  for (size_t n = 0; n < blob.size(); n += 7) {
    auto r = decodeChunk(std::span(blob.data(), n), "truncated");
    EXPECT_FALSE(r.ok());
  }
  std::mt19937 rng(5);
  int rejected = 0;
  for (int i = 0; i < 2000; ++i) {
    std::vector<uint8_t> bad = blob;
    bad[rng() % bad.size()] ^= uint8_t(1u << (rng() % 8));
    auto r = decodeChunk(bad, "flipped");
    if (!r.ok()) {
      ++rejected;
      EXPECT_NE(r.error().message.find("flipped: corrupt chunk"), std::string::npos);
      continue;
    }
    for (const ChunkPart& p : r->parts)
      for (uint32_t index : p.indices) ASSERT_LT(index, p.vertices.size());
  }
  EXPECT_GT(rejected, 0);
  std::vector<uint8_t> noise(300);
  for (auto& b : noise) b = uint8_t(rng());
  EXPECT_FALSE(decodeChunk(noise, "noise").ok());
}

// makeGeometry's surface alone (its vertices span 0 .. 3n on both axes), with skirt depths.
ChunkGeometry surfaceOnly(int n, uint32_t seed, std::array<uint16_t, 4> skirtSteps) {
  ChunkGeometry g = makeGeometry(n, seed);
  ChunkPart& p = g.parts[0];
  p.vertices.resize(size_t(n + 1) * (n + 1));
  p.indices.resize(p.surfaceIndexCount);
  g.zBase = 1234 * g.zStep;  // version 2 stores it in whole steps
  g.skirtSteps = skirtSteps;
  return g;
}

// Payload version 2: the reader hangs a skirt from every side with a depth, outwards, each
// bottom that many steps below its top; the surface round-trips as stored.
TEST(ChunkCodec, DerivedSkirtsHangOutwardsFromTheSidesWithADepth) {
  const int n = 8;
  const ChunkGeometry g = surfaceOnly(n, 6, {100, 0, 200, 50});  // south, -, north, west
  const std::vector<uint8_t> blob = encodeChunk(g, 3, ChunkPayloadVersion::kDerivedSkirts);
  auto decoded = decodeChunk(blob, "test");
  ASSERT_TRUE(decoded.ok()) << decoded.error().message;
  EXPECT_EQ(decoded->zBase, g.zBase);
  EXPECT_EQ(decoded->skirtSteps, g.skirtSteps);
  const ChunkPart &p = decoded->parts[0], &o = g.parts[0];
  ASSERT_EQ(p.surfaceIndexCount, o.surfaceIndexCount);
  EXPECT_EQ(triangles(p, 0, p.surfaceIndexCount), triangles(o, 0, o.surfaceIndexCount));
  // A bottom per side vertex of the three sides, two triangles per side edge.
  EXPECT_EQ(p.vertices.size(), o.vertices.size() + 3 * size_t(n + 1));
  EXPECT_EQ(p.indices.size() - p.surfaceIndexCount, 3 * 2 * 3 * size_t(n));
  const int side = 3 * n;
  for (size_t k = p.surfaceIndexCount; k < p.indices.size(); k += 3) {
    std::array<std::array<double, 3>, 3> v;
    for (int j = 0; j < 3; ++j) {
      const ChunkVertex& c = p.vertices[p.indices[k + j]];
      v[j] = {double(c.x), double(c.y), double(c.z)};
    }
    // Which side: the coordinate all three share.
    std::array<double, 2> outwards{};
    if (v[0][1] == 0 && v[1][1] == 0 && v[2][1] == 0)
      outwards = {0, -1};
    else if (v[0][1] == side && v[1][1] == side && v[2][1] == side)
      outwards = {0, 1};
    else if (v[0][0] == 0 && v[1][0] == 0 && v[2][0] == 0)
      outwards = {-1, 0};
    else
      FAIL() << "a skirt triangle off the skirted sides";
    const std::array<double, 3> e1 = {v[1][0] - v[0][0], v[1][1] - v[0][1], v[1][2] - v[0][2]},
                                e2 = {v[2][0] - v[0][0], v[2][1] - v[0][1], v[2][2] - v[0][2]};
    const double nx = e1[1] * e2[2] - e1[2] * e2[1], ny = e1[2] * e2[0] - e1[0] * e2[2];
    EXPECT_GT(nx * outwards[0] + ny * outwards[1], 0) << "faces inwards";
  }
  // Each bottom lies its side's steps below the top at its (x, y).
  for (size_t i = o.vertices.size(); i < p.vertices.size(); ++i) {
    const ChunkVertex& b = p.vertices[i];
    const ChunkVertex& top = o.vertices[size_t(b.y / 3) * (n + 1) + b.x / 3];
    const int steps = top.z - b.z;
    EXPECT_TRUE(steps == 100 || steps == 200 || steps == 50) << steps;
    EXPECT_EQ(b.morphDelta, top.morphDelta);
  }
  // No depth anywhere: no skirts.
  auto bare = decodeChunk(
      encodeChunk(surfaceOnly(n, 6, {}), 3, ChunkPayloadVersion::kDerivedSkirts), "test");
  ASSERT_TRUE(bare.ok());
  EXPECT_EQ(bare->parts[0].indices.size(), bare->parts[0].surfaceIndexCount);
}

TEST(ChunkCodec, DerivedSkirtsBelowTheHeightRangeAreRefused) {
  // makeGeometry's heights are 30000 .. 31999: 40000 steps down is below 0.
  const auto r = decodeChunk(
      encodeChunk(surfaceOnly(4, 7, {0, 40000, 0, 0}), 3, ChunkPayloadVersion::kDerivedSkirts),
      "c");
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().message, "c: corrupt chunk: skirt reaches below the height range");
}

std::vector<uint8_t> decompress(const std::vector<uint8_t>& blob) {
  std::vector<uint8_t> raw(ZSTD_getFrameContentSize(blob.data(), blob.size()));
  EXPECT_EQ(ZSTD_decompress(raw.data(), raw.size(), blob.data(), blob.size()), raw.size());
  return raw;
}
std::vector<uint8_t> compress(const std::vector<uint8_t>& raw) {
  std::vector<uint8_t> blob(ZSTD_compressBound(raw.size()));
  blob.resize(ZSTD_compress(blob.data(), blob.size(), raw.data(), raw.size(), 1));
  return blob;
}
long peakResidentKb() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_maxrss;
}

// Found by profiling the chunk fuzzer: a part header could claim up to 2^24 indices over a
// stream of a few bytes, and 64 MiB were allocated before the stream failed to decode.
TEST(ChunkCodec, PartsClaimingMoreIndicesThanTheirStreamHoldsAreRefused) {
  std::vector<uint8_t> raw = decompress(encodeChunk(makeGeometry(4, 1)));
  const size_t indexCountAt = 24 + 4;  // after the payload header, in part 0's header
  const uint32_t claimed = 3u << 20;
  std::memcpy(raw.data() + indexCountAt, &claimed, sizeof claimed);
  const auto r = decodeChunk(compress(raw), "c");
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().message, "c: corrupt chunk: bad part header");
}

// A frame that claims 250 MiB and holds 24 bytes fails without touching 250 MiB of memory.
// Version 2's header is 28 bytes: a payload that ends inside it is refused before any read.
TEST(ChunkCodec, AVersionTwoPayloadShorterThanItsHeaderIsRefused) {
  std::vector<uint8_t> raw = decompress(
      encodeChunk(surfaceOnly(4, 1, {5, 5, 5, 5}), 3, ChunkPayloadVersion::kDerivedSkirts));
  ASSERT_EQ(raw[4], 2);  // payload version
  raw.resize(26);
  const auto r = decodeChunk(compress(raw), "c");
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().message, "c: corrupt chunk: implausible size");
}

TEST(ChunkCodec, AFrameClaimingAHugeSizeCostsNoMemory) {
  const uint64_t claimed = 250ull << 20;
  std::vector<uint8_t> frame = {0x28, 0xB5, 0x2F, 0xFD, 0xE0};  // magic; 8-byte size, 1 segment
  for (int i = 0; i < 8; ++i) frame.push_back(uint8_t(claimed >> (8 * i)));
  frame.insert(frame.end(), {(24 << 3) | 1, 0, 0});  // the last block: raw, 24 bytes
  frame.insert(frame.end(), 24, 0x42);
  ASSERT_EQ(ZSTD_getFrameContentSize(frame.data(), frame.size()), claimed);
  const long before = peakResidentKb();
  const auto r = decodeChunk(frame, "c");
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().message, "c: corrupt chunk: zstd data does not decompress");
  EXPECT_LT(peakResidentKb() - before, 100 * 1024) << "kilobytes";
}

}  // namespace
}  // namespace terralod
