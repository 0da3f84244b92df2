#include "terralod/format/rtin_chunk_codec.h"

#include <zstd.h>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <unordered_map>

#include "terralod/core/bintree.h"
#include "terralod/format/byte_io.h"
#include "zstd_frame.h"

namespace terralod {
namespace {

constexpr uint32_t kRtinChunkMagic = 0x42434C54;  // "TLCB"
constexpr uint16_t kRtinPayloadVersion = 3;
// magic, version, sideLog2, flags, zStep, zBaseSteps, skirtSteps[4], clipX, clipY,
// vertexCount, triangleCount, bitBytes, zBytes, deltaBytes
constexpr size_t kRtinHeaderBytes = 4 + 2 + 1 + 1 + 8 + 4 + 8 + 4 + 5 * 4;
constexpr uint8_t kRtinFlagRising = 1, kRtinFlagHasParent = 2, kRtinFlagFramedStreams = 4;
constexpr int kRtinMaxSideLog2 = 15;  // local coordinates are 16-bit
constexpr uint64_t kRtinMaxStreamBytes = uint64_t{1} << 28;

class BitWriter {
 public:
  void put(bool bit) {
    if (mCount % 8 == 0) mBytes.push_back(0);
    if (bit) mBytes.back() |= uint8_t(1u << (mCount % 8));
    ++mCount;
  }
  const std::vector<uint8_t>& bytes() const { return mBytes; }

 private:
  std::vector<uint8_t> mBytes;
  size_t mCount = 0;
};

class BitReader {
 public:
  explicit BitReader(std::span<const uint8_t> bytes) : mBytes(bytes) {}
  /// The next bit; past the end, false and failed() from then on.
  bool get() {
    if (mCount >= mBytes.size() * 8) {
      mFailed = true;
      return false;
    }
    const bool bit = (mBytes[mCount / 8] >> (mCount % 8)) & 1u;
    ++mCount;
    return bit;
  }
  bool failed() const { return mFailed; }
  /// Every bit used (the rest of the last byte zero).
  bool exhausted() const {
    if (mCount + 8 <= mBytes.size() * 8) return false;
    return mCount % 8 == 0 || (mBytes.back() >> (mCount % 8)) == 0;
  }

 private:
  std::span<const uint8_t> mBytes;
  size_t mCount = 0;
  bool mFailed = false;
};

void putVarint(std::vector<uint8_t>& out, int32_t value) {
  uint32_t v = (uint32_t(value) << 1) ^ uint32_t(value >> 31);  // zigzag
  while (v >= 0x80) {
    out.push_back(uint8_t(v | 0x80));
    v >>= 7;
  }
  out.push_back(uint8_t(v));
}

class VarintReader {
 public:
  explicit VarintReader(std::span<const uint8_t> bytes) : mBytes(bytes) {}
  /// The next value; on a truncated or overlong value, 0 and failed() from then on.
  int32_t get() {
    uint32_t v = 0;
    for (int shift = 0; shift < 35; shift += 7) {
      if (mPos >= mBytes.size()) break;
      const uint8_t b = mBytes[mPos++];
      v |= uint32_t(b & 0x7F) << shift;
      if (!(b & 0x80)) return int32_t(v >> 1) ^ -int32_t(v & 1);
    }
    mFailed = true;
    return 0;
  }
  bool failed() const { return mFailed; }
  bool exhausted() const { return mPos == mBytes.size(); }

 private:
  std::span<const uint8_t> mBytes;
  size_t mPos = 0;
  bool mFailed = false;
};

// Grid point to vertex number over the chunk's square: dense for small squares.
class PointIndex {
 public:
  explicit PointIndex(int32_t side) : mStride(side + 1) {
    if (size_t(mStride) * size_t(mStride) <= (size_t{1} << 20))
      mDense.assign(size_t(mStride) * size_t(mStride), -1);
  }
  int32_t find(GridPoint p) const {
    if (!mDense.empty()) return mDense[size_t(p.y) * mStride + p.x];
    const auto it = mSparse.find(key(p));
    return it == mSparse.end() ? -1 : it->second;
  }
  /// The vertex at p, numbered `next` if it has none yet.
  int32_t findOrAdd(GridPoint p, int32_t next) {
    if (!mDense.empty()) {
      int32_t& slot = mDense[size_t(p.y) * mStride + p.x];
      if (slot < 0) slot = next;
      return slot;
    }
    return mSparse.try_emplace(key(p), next).first->second;
  }

 private:
  static uint64_t key(GridPoint p) { return (uint64_t(uint32_t(p.y)) << 32) | uint32_t(p.x); }
  int32_t mStride;
  std::vector<int32_t> mDense;
  std::unordered_map<uint64_t, int32_t> mSparse;
};

struct Split {
  GridPoint a, b, m;
  bool parentSplits = false;
};

// The chunk's surface as the mesher's walk makes it (ChunkMesher::build): triangles in its
// order, vertices numbered in the order the index list first names them, triangles clipped to
// the data inside the square.
struct Walk {
  std::vector<GridPoint> positions;
  std::vector<uint32_t> indices;
  std::vector<Split> splits;
  PointIndex index;
  explicit Walk(int32_t side) : index(side) {}
};

struct Decision {
  bool ok = true;
  bool split = false, parentSplits = false;
};

// Walks the bintree of the square (0, 0)-(side, side); `decide(t, depth, inParent)` says
// whether t splits, where inParent is what the walk knows (for depth 0: unknown). Stops and
// returns false when `decide` fails or the vertices pass `vertexLimit`.
template <typename Decide>
bool walkChunk(int sideLog2, bool rising, uint16_t clipX, uint16_t clipY, size_t vertexLimit,
               Decide&& decide, Walk& walk) {
  const int32_t side = int32_t{1} << sideLog2;
  const GridPoint sw{0, 0}, se{side, 0}, nw{0, side}, ne{side, side};
  const std::array<BinTriangle, 2> roots =
      rising ? std::array{BinTriangle{sw, ne, se}, BinTriangle{sw, ne, nw}}
             : std::array{BinTriangle{nw, se, sw}, BinTriangle{nw, se, ne}};
  struct Item {
    BinTriangle t;
    int depth;
    bool inParent;
  };
  std::vector<Item> stack = {{roots[0], 0, false}, {roots[1], 0, false}};
  const int32_t w = clipX, h = clipY;

  auto vertex = [&](GridPoint p) {
    const int32_t next = int32_t(walk.positions.size());
    const int32_t i = walk.index.findOrAdd(p, next);
    if (i == next) walk.positions.push_back(p);
    return uint32_t(i);
  };
  auto addTriangle = [&](GridPoint a, GridPoint b, GridPoint c) {
    const int64_t o = orient2d(a, b, c);
    if (o == 0) return;
    const GridPoint second = o > 0 ? b : c, third = o > 0 ? c : b;
    const uint32_t i0 = vertex(a);
    const uint32_t i1 = vertex(second);
    const uint32_t i2 = vertex(third);
    walk.indices.insert(walk.indices.end(), {i0, i1, i2});
  };
  auto emit = [&](const BinTriangle& t) {
    const int32_t maxX = std::max({t.a.x, t.b.x, t.apex.x}),
                  maxY = std::max({t.a.y, t.b.y, t.apex.y});
    const int32_t minX = std::min({t.a.x, t.b.x, t.apex.x}),
                  minY = std::min({t.a.y, t.b.y, t.apex.y});
    if (minX >= w || minY >= h) return;
    GridPoint poly[8] = {t.a, t.b, t.apex};
    int n = 3;
    if (maxX <= w && maxY <= h) {
      addTriangle(poly[0], poly[1], poly[2]);
      return;
    }
    auto clip = [&](bool alongX, int32_t limit) {
      GridPoint out[8];
      int m = 0;
      for (int i = 0; i < n; ++i) {
        const GridPoint p = poly[i], q = poly[(i + 1) % n];
        const int32_t pc = alongX ? p.x : p.y, qc = alongX ? q.x : q.y;
        if (pc <= limit) out[m++] = p;
        if (int64_t(pc - limit) * (qc - limit) < 0) {
          const int32_t po = alongX ? p.y : p.x, qo = alongX ? q.y : q.x;
          const int32_t other = po + int32_t(int64_t(limit - pc) * (qo - po) / (qc - pc));
          out[m++] = alongX ? GridPoint{limit, other} : GridPoint{other, limit};
        }
      }
      n = m;
      std::copy(out, out + m, poly);
    };
    if (maxX > w) clip(true, w);
    if (maxY > h) clip(false, h);
    for (int i = 1; i + 1 < n; ++i) addTriangle(poly[0], poly[i], poly[i + 1]);
  };

  while (!stack.empty()) {
    const Item item = stack.back();
    stack.pop_back();
    if (!item.t.splittable()) {
      emit(item.t);
    } else {
      const Decision d = decide(item.t, item.depth, item.inParent);
      if (!d.ok) return false;
      if (d.split) {
        walk.splits.push_back({item.t.a, item.t.b, item.t.hypotenuseMidpoint(), d.parentSplits});
        const auto kids = item.t.children();
        const int first = (item.depth & 1) ? 1 : 0;
        stack.push_back({kids[1 - first], item.depth + 1, d.parentSplits});
        stack.push_back({kids[first], item.depth + 1, d.parentSplits});
      } else {
        emit(item.t);
      }
    }
    if (walk.positions.size() > vertexLimit) return false;
  }
  return true;
}

// The order heights are coded in, with each vertex's predictors: the square's corners, then
// each split's midpoint (predicted from its hypotenuse's ends, coded before it), then the
// vertices the clip made.
struct Coded {
  uint32_t vertex;
  int32_t a = -1, b = -1;     ///< predictor vertices (-1: none)
  bool parentVertex = false;  ///< the parent splits here: the vertex is the parent's own
};

std::vector<Coded> codingOrder(const Walk& walk, int32_t side) {
  const size_t n = walk.positions.size();
  std::vector<uint8_t> done(n, 0);
  std::vector<Coded> order;
  order.reserve(n);
  for (const GridPoint c :
       {GridPoint{0, 0}, GridPoint{side, 0}, GridPoint{0, side}, {side, side}}) {
    const int32_t i = c.x <= side && c.y <= side ? walk.index.find(c) : -1;
    if (i >= 0 && !done[size_t(i)]) {
      done[size_t(i)] = 1;
      order.push_back({uint32_t(i)});
    }
  }
  for (const Split& s : walk.splits) {
    const int32_t i = walk.index.find(s.m);
    if (i < 0 || done[size_t(i)]) continue;
    done[size_t(i)] = 1;
    const int32_t a = walk.index.find(s.a), b = walk.index.find(s.b);
    order.push_back({uint32_t(i), a >= 0 && done[size_t(a)] ? a : -1,
                     b >= 0 && done[size_t(b)] ? b : -1, s.parentSplits});
  }
  for (uint32_t i = 0; i < n; ++i)
    if (!done[i]) order.push_back({i});
  return order;
}

// The predicted height and morph target (zStep units from zBase) of `c`, from what is coded.
struct Prediction {
  int32_t z, target;
};
Prediction predict(const Coded& c, const std::vector<ChunkVertex>& v, Prediction previous) {
  auto targetOf = [&](int32_t i) { return int32_t(v[size_t(i)].z) + v[size_t(i)].morphDelta; };
  if (c.a >= 0 && c.b >= 0) {
    const int32_t z = (int32_t(v[size_t(c.a)].z) + v[size_t(c.b)].z) >> 1;
    return {z, c.parentVertex ? z : (targetOf(c.a) + targetOf(c.b)) >> 1};
  }
  const int32_t one = c.a >= 0 ? c.a : c.b;
  if (one >= 0) return {v[size_t(one)].z, targetOf(one)};
  return previous;
}

}  // namespace

std::optional<std::vector<uint8_t>> encodeRtinChunk(const RtinChunkInput& chunk,
                                                    int compressionLevel) {
  if (chunk.sideLog2 < 1 || chunk.sideLog2 > kRtinMaxSideLog2) return std::nullopt;
  const int32_t side = int32_t{1} << chunk.sideLog2;
  BitWriter bits;
  size_t next = 0;
  bool consistent = true;
  auto decide = [&](const BinTriangle&, int depth, bool walkInParent) -> Decision {
    if (next >= chunk.decisions.size()) return {false};
    const uint8_t d = chunk.decisions[next++];
    const bool inParent = chunk.hasParent && (d & kRtinInParent);
    if (depth == 0) {
      if (chunk.hasParent) bits.put(inParent);
    } else if (inParent != walkInParent) {
      consistent = false;
      return {false};
    }
    const bool split = d & kRtinSplit;
    const bool parentSplits = split && inParent && (d & kRtinParentSplits);
    bits.put(split);
    if (split && inParent) bits.put(parentSplits);
    return {true, split, parentSplits};
  };
  Walk walk(side);
  if (!walkChunk(chunk.sideLog2, chunk.rising, chunk.clipX, chunk.clipY, chunk.vertices.size(),
                 decide, walk) ||
      !consistent || next != chunk.decisions.size())
    return std::nullopt;
  // The walk must give the mesher's surface exactly.
  if (walk.positions.size() != chunk.vertices.size() ||
      !std::equal(walk.indices.begin(), walk.indices.end(), chunk.indices.begin(),
                  chunk.indices.end()))
    return std::nullopt;
  for (size_t i = 0; i < walk.positions.size(); ++i)
    if (walk.positions[i].x != chunk.vertices[i].x || walk.positions[i].y != chunk.vertices[i].y)
      return std::nullopt;

  const std::vector<ChunkVertex> vertices(chunk.vertices.begin(), chunk.vertices.end());
  std::vector<uint8_t> zStream, deltaStream;
  Prediction previous{0, 0};
  for (const Coded& c : codingOrder(walk, side)) {
    const Prediction p = predict(c, vertices, previous);
    const ChunkVertex& v = vertices[c.vertex];
    const int32_t target = int32_t(v.z) + v.morphDelta;
    putVarint(zStream, int32_t(v.z) - p.z);
    putVarint(deltaStream, (target - p.target) - (int32_t(v.z) - p.z));
    previous = {v.z, target};
  }

  // The streams as they are in the blob's one frame, or each in its own zstd frame inside it:
  // one Huffman table over the three costs large chunks about 5 %, three tables cost small
  // chunks more than that. Whichever is smaller.
  const std::vector<uint8_t>* plain[3] = {&bits.bytes(), &zStream, &deltaStream};
  auto blobOf = [&](bool separate) {
    std::vector<uint8_t> framed[3];
    const std::vector<uint8_t>* streams[3] = {plain[0], plain[1], plain[2]};
    if (separate)
      for (int k = 0; k < 3; ++k) {
        framed[k] = zstdFrame(*plain[k], compressionLevel);
        streams[k] = &framed[k];
      }
    std::vector<uint8_t> raw(kRtinHeaderBytes + streams[0]->size() + streams[1]->size() +
                             streams[2]->size());
    ByteWriter w(raw.data());
    w.put<uint32_t>(kRtinChunkMagic);
    w.put<uint16_t>(kRtinPayloadVersion);
    w.put<uint8_t>(uint8_t(chunk.sideLog2));
    w.put<uint8_t>(uint8_t((chunk.rising ? kRtinFlagRising : 0) |
                           (chunk.hasParent ? kRtinFlagHasParent : 0) |
                           (separate ? kRtinFlagFramedStreams : 0)));
    w.put<double>(chunk.zStep);
    w.put<int32_t>(chunk.zBaseSteps);
    for (uint16_t steps : chunk.skirtSteps) w.put<uint16_t>(steps);
    w.put<uint16_t>(chunk.clipX);
    w.put<uint16_t>(chunk.clipY);
    w.put<uint32_t>(uint32_t(vertices.size()));
    w.put<uint32_t>(uint32_t(walk.indices.size() / 3));
    for (const auto* stream : streams) w.put<uint32_t>(uint32_t(stream->size()));
    for (const auto* stream : streams) w.putBytes(stream->data(), stream->size());
    // Framed streams leave the blob's frame nothing to compress: level 1.
    return zstdFrame(raw, separate ? 1 : compressionLevel);
  };
  std::vector<uint8_t> one = blobOf(false), framed = blobOf(true);
  return framed.size() < one.size() ? framed : one;
}

Result<ChunkGeometry> decodeRtinPayload(std::span<const uint8_t> raw, const std::string& subject) {
  auto bad = [&](const std::string& what) { return makeError(subject, "corrupt chunk: " + what); };
  if (raw.size() < kRtinHeaderBytes) return bad("implausible size");
  ByteReader r(raw.data());
  if (r.get<uint32_t>() != kRtinChunkMagic || r.get<uint16_t>() != kRtinPayloadVersion)
    return bad("not an RTIN chunk payload");
  const int sideLog2 = r.get<uint8_t>();
  const uint8_t flags = r.get<uint8_t>();
  ChunkGeometry g;
  g.zStep = r.get<double>();
  const int32_t baseSteps = r.get<int32_t>();
  g.zBase = baseSteps * g.zStep;
  for (uint16_t& steps : g.skirtSteps) steps = r.get<uint16_t>();
  const uint16_t clipX = r.get<uint16_t>(), clipY = r.get<uint16_t>();
  const uint32_t vertexCount = r.get<uint32_t>(), triangleCount = r.get<uint32_t>();
  const uint32_t bitBytes = r.get<uint32_t>(), zBytes = r.get<uint32_t>(),
                 deltaBytes = r.get<uint32_t>();
  if (sideLog2 < 1 || sideLog2 > kRtinMaxSideLog2 ||
      (flags & ~(kRtinFlagRising | kRtinFlagHasParent | kRtinFlagFramedStreams)))
    return bad("bad square");
  const int32_t side = int32_t{1} << sideLog2;
  if (!std::isfinite(g.zBase) || !(g.zStep > 0) || !std::isfinite(g.zStep))
    return bad("bad height scale");
  if (clipX == 0 || clipY == 0 || clipX > side || clipY > side) return bad("bad data extent");
  const uint64_t gridPoints = uint64_t(side + 1) * uint64_t(side + 1);
  if (vertexCount < 3 || vertexCount > gridPoints || triangleCount == 0 ||
      triangleCount > 2 * uint64_t(side) * side)
    return bad("bad vertex or triangle count");
  if (uint64_t(kRtinHeaderBytes) + bitBytes + zBytes + deltaBytes != raw.size())
    return bad("stream sizes do not match the data");
  // With kRtinFlagFramedStreams each stream is one zstd frame. A varint takes 1 to 5 bytes,
  // and every vertex has one of each.
  std::vector<uint8_t> streams[3];
  const uint32_t streamBytes[3] = {bitBytes, zBytes, deltaBytes};
  const uint64_t most[3] = {kRtinMaxStreamBytes, 5 * uint64_t(vertexCount),
                            5 * uint64_t(vertexCount)};
  size_t at = kRtinHeaderBytes;
  for (int k = 0; k < 3; ++k) {
    const std::span<const uint8_t> stored = raw.subspan(at, streamBytes[k]);
    at += streamBytes[k];
    if (!(flags & kRtinFlagFramedStreams)) {
      streams[k].assign(stored.begin(), stored.end());
    } else {
      const unsigned long long size = ZSTD_getFrameContentSize(stored.data(), stored.size());
      if (size == ZSTD_CONTENTSIZE_ERROR || size == ZSTD_CONTENTSIZE_UNKNOWN || size > most[k])
        return bad("implausible stream");
      streams[k].resize(size);
      const size_t got = ZSTD_decompress(streams[k].data(), size, stored.data(), stored.size());
      if (ZSTD_isError(got) || got != size) return bad("stream does not decompress");
    }
    if (k > 0 && (streams[k].size() < vertexCount || streams[k].size() > most[k]))
      return bad("height streams do not fit the vertices");
  }

  const bool hasParent = flags & kRtinFlagHasParent;
  BitReader bits(streams[0]);
  auto decide = [&](const BinTriangle&, int depth, bool walkInParent) -> Decision {
    const bool inParent = depth == 0 ? hasParent && bits.get() : walkInParent;
    const bool split = bits.get();
    const bool parentSplits = split && inParent && bits.get();
    return {!bits.failed(), split, parentSplits};
  };
  Walk walk(side);
  if (!walkChunk(sideLog2, flags & kRtinFlagRising, clipX, clipY, vertexCount, decide, walk) ||
      !bits.exhausted())
    return bad("split bits do not match the chunk");
  if (walk.positions.size() != vertexCount || walk.indices.size() != 3 * size_t(triangleCount))
    return bad("split bits do not give the stored counts");

  std::vector<ChunkVertex> vertices(vertexCount);
  for (size_t i = 0; i < vertexCount; ++i)
    vertices[i] = {uint16_t(walk.positions[i].x), uint16_t(walk.positions[i].y), 0, 0};
  VarintReader zs(streams[1]);
  VarintReader ds(streams[2]);
  Prediction previous{0, 0};
  for (const Coded& c : codingOrder(walk, side)) {
    const Prediction p = predict(c, vertices, previous);
    const int64_t zResidual = zs.get();
    const int64_t z = p.z + zResidual;
    const int64_t target = p.target + zResidual + ds.get();
    const int64_t delta = target - z;
    if (zs.failed() || ds.failed() || z < 0 || z > 65535 || delta < -32768 || delta > 32767)
      return bad("height out of range");
    ChunkVertex& v = vertices[c.vertex];
    v.z = uint16_t(z);
    v.morphDelta = int16_t(delta);
    previous = {int32_t(z), int32_t(target)};
  }
  if (!zs.exhausted() || !ds.exhausted()) return bad("height streams longer than the vertices");

  g.parts = splitChunkParts(vertices, std::move(walk.indices), {}, g.skirtSteps, uint16_t(side));
  const Status skirts = appendDerivedSkirts(g);
  if (!skirts) return bad(skirts.error().message);
  return g;
}

}  // namespace terralod
