#include "terralod/format/rtin_chunk_codec.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <optional>

#include "range_coder.h"
#include "terralod/core/bintree.h"
#include "terralod/core/key_hash.h"
#include "terralod/core/touched_index.h"
#include "terralod/format/byte_io.h"
#include "zstd_frame.h"

namespace terralod {
namespace {

constexpr uint32_t kRtinChunkMagic = 0x42434C54;  // "TLCB"
constexpr uint16_t kRtinPayloadVersion = 3;
// magic, version, sideLog2, flags, zStep, zBaseSteps, skirtSteps[4], clipX, clipY,
// vertexCount, triangleCount, decisionCount, codedBytes
constexpr size_t kRtinHeaderBytes = 4 + 2 + 1 + 1 + 8 + 4 + 8 + 4 + 4 * 4;
// A chunk's most vertices and triangles (a 4096-cell square at full resolution has 2^25
// triangles); more is refused before anything is allocated for it.
constexpr uint32_t kRtinMaxCount = uint32_t{1} << 26;
constexpr uint8_t kRtinFlagRising = 1, kRtinFlagHasParent = 2;
constexpr int kRtinMaxSideLog2 = 15;  // local coordinates are 16-bit
// Depths of the bintree below the chunk's square (at most 2 · 15), and one more context for
// the vertices coded without a split (the square's corners, those the clip makes).
constexpr int kRtinDepths = 32;

// The odds the decisions and residuals are coded with, each in its context: split decisions
// by depth and whether the triangle is the parent level's, heights by their split's depth,
// morph deltas by depth and whether the vertex is the parent's own.
struct Models {
  std::array<rc::Probability, 2 * kRtinDepths> split;
  rc::Probability rootInParent;
  std::array<rc::Probability, kRtinDepths> parentSplits;
  std::array<rc::IntegerModel, kRtinDepths + 1> z;
  std::array<rc::IntegerModel, 2 * (kRtinDepths + 1)> delta;
};

// The dense table stays with its thread from chunk to chunk: a fresh (side+1)^2 table per
// chunk cost 360 MB of fills and 6,000 page faults in an 8193^2 build. Only for squares up to
// kThreadTableSide cells (1 MB): the runtime's loader threads decode chunks too, and a table
// they kept for 2048-cell chunks would hold 16 MB each outside the memory budget.
constexpr size_t kThreadTableSide = 512;
struct ThreadTable {
  TouchedIndex index;
  bool inUse = false;
};
thread_local ThreadTable tThreadTable;

// Grid point to vertex number over the chunk's square: the thread's dense table for small
// squares, a hash sized from the vertex count for larger ones: a coarse chunk has a few
// thousand vertices in a square of up to 8193^2 grid points, and a dense table per chunk cost a
// 4-16 MB fill each (a twentieth of an 8193^2 build).
class PointIndex {
 public:
  PointIndex(int32_t side, size_t expectedVertices) : mStride(uint32_t(side) + 1) {
    const size_t n = size_t(mStride) * size_t(mStride);
    const size_t most = (kThreadTableSide + 1) * (kThreadTableSide + 1);
    if (n <= most && !tThreadTable.inUse) {
      tThreadTable.inUse = true;
      mDense = &tThreadTable.index;
      mDense->reserve(n);
    } else {
      mHash.emplace(expectedVertices);  // large, or a walk inside a walk
    }
  }
  ~PointIndex() {
    if (!mDense) return;
    mDense->clear();
    tThreadTable.inUse = false;
  }
  PointIndex(const PointIndex&) = delete;
  PointIndex& operator=(const PointIndex&) = delete;

  int32_t find(GridPoint p) const {
    return mDense ? mDense->find(key(p)) : mHash->find(uint32_t(key(p)));
  }
  /// The vertex at p, numbered `next` if it has none yet.
  int32_t findOrAdd(GridPoint p, int32_t next) {
    return mDense ? mDense->findOrAdd(key(p), next) : mHash->findOrAdd(uint32_t(key(p)), next);
  }

 private:
  // Below 2^32 for every square (sides up to 2^15 cells).
  size_t key(GridPoint p) const { return size_t(p.y) * mStride + size_t(p.x); }
  uint32_t mStride;
  TouchedIndex* mDense = nullptr;
  std::optional<KeyHash> mHash;
};

struct Split {
  GridPoint a, b, m;
  int depth = 0;
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
  Walk(int32_t side, size_t expectedVertices) : index(side, expectedVertices) {}
};

// A corner of a leaf being clipped to the data (clipToLine).
struct Corner {
  GridPoint p;
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
  const std::array<BinTriangle, 2> roots = squareTriangles(0, 0, side, rising);
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
    Corner poly[8] = {{t.a}, {t.b}, {t.apex}};
    int n = 3;
    if (maxX <= w && maxY <= h) {
      addTriangle(t.a, t.b, t.apex);
      return;
    }
    auto between = [](const Corner&, const Corner&, double) { return Corner{}; };
    if (maxX > w) clipToLine(poly, n, true, w, between);
    if (maxY > h) clipToLine(poly, n, false, h, between);
    for (int i = 1; i + 1 < n; ++i) addTriangle(poly[0].p, poly[i].p, poly[i + 1].p);
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
        walk.splits.push_back(
            {item.t.a, item.t.b, item.t.hypotenuseMidpoint(), item.depth, d.parentSplits});
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
  int context = kRtinDepths;  ///< its split's depth; kRtinDepths without a split
};

std::vector<Coded> codingOrder(const Walk& walk, int32_t side) {
  const size_t n = walk.positions.size();
  std::vector<uint8_t> done(n, 0);
  std::vector<Coded> order;
  order.reserve(n);
  for (const GridPoint c :
       {GridPoint{0, 0}, GridPoint{side, 0}, GridPoint{0, side}, {side, side}}) {
    const int32_t i = walk.index.find(c);
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
                     b >= 0 && done[size_t(b)] ? b : -1, s.parentSplits,
                     std::min(s.depth, kRtinDepths - 1)});
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

std::optional<std::vector<uint8_t>> encodeRtinChunk(const RtinChunkInput& chunk) {
  if (chunk.sideLog2 < 1 || chunk.sideLog2 > kRtinMaxSideLog2) return std::nullopt;
  const int32_t side = int32_t{1} << chunk.sideLog2;
  auto models = std::make_unique<Models>();
  rc::Encoder coder;
  size_t next = 0;
  auto decide = [&](const BinTriangle&, int depth, bool walkInParent) -> Decision {
    if (next >= chunk.decisions.size()) return {false};
    const uint8_t d = chunk.decisions[next++];
    const bool inParent = chunk.hasParent && (d & kRtinInParent);
    if (depth == 0) {
      if (chunk.hasParent) coder.bit(models->rootInParent, inParent);
    } else if (inParent != walkInParent) {
      return {false};
    }
    const bool split = d & kRtinSplit;
    const bool parentSplits = split && inParent && (d & kRtinParentSplits);
    const int context = std::min(depth, kRtinDepths - 1);
    coder.bit(models->split[size_t(context * 2 + (inParent ? 1 : 0))], split);
    if (split && inParent) coder.bit(models->parentSplits[size_t(context)], parentSplits);
    return {true, split, parentSplits};
  };
  Walk walk(side, chunk.vertices.size());
  walk.positions.reserve(chunk.vertices.size());
  walk.indices.reserve(chunk.indices.size());
  walk.splits.reserve(chunk.vertices.size());
  if (!walkChunk(chunk.sideLog2, chunk.rising, chunk.clipX, chunk.clipY, chunk.vertices.size(),
                 decide, walk) ||
      next != chunk.decisions.size())
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
  Prediction previous{0, 0};
  for (const Coded& c : codingOrder(walk, side)) {
    const Prediction p = predict(c, vertices, previous);
    const ChunkVertex& v = vertices[c.vertex];
    const int32_t target = int32_t(v.z) + v.morphDelta;
    rc::encodeInteger(coder, models->z[size_t(c.context)], int32_t(v.z) - p.z);
    rc::encodeInteger(coder, models->delta[size_t(c.context * 2 + (c.parentVertex ? 1 : 0))],
                      (target - p.target) - (int32_t(v.z) - p.z));
    previous = {v.z, target};
  }
  const std::vector<uint8_t> coded = coder.finish();

  std::vector<uint8_t> raw(kRtinHeaderBytes + coded.size());
  ByteWriter w(raw.data());
  w.put<uint32_t>(kRtinChunkMagic);
  w.put<uint16_t>(kRtinPayloadVersion);
  w.put<uint8_t>(uint8_t(chunk.sideLog2));
  w.put<uint8_t>(
      uint8_t((chunk.rising ? kRtinFlagRising : 0) | (chunk.hasParent ? kRtinFlagHasParent : 0)));
  w.put<double>(chunk.zStep);
  w.put<int32_t>(chunk.zBaseSteps);
  for (uint16_t steps : chunk.skirtSteps) w.put<uint16_t>(steps);
  w.put<uint16_t>(chunk.clipX);
  w.put<uint16_t>(chunk.clipY);
  w.put<uint32_t>(uint32_t(vertices.size()));
  w.put<uint32_t>(uint32_t(walk.indices.size() / 3));
  w.put<uint32_t>(uint32_t(chunk.decisions.size()));
  w.put<uint32_t>(uint32_t(coded.size()));
  w.putBytes(coded.data(), coded.size());
  // Range-coded bytes leave zstd (the container every chunk blob is) nothing to find.
  return zstdFrame(raw, 1);
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
  const uint32_t decisionCount = r.get<uint32_t>(), codedBytes = r.get<uint32_t>();
  if (sideLog2 < 1 || sideLog2 > kRtinMaxSideLog2 ||
      (flags & ~(kRtinFlagRising | kRtinFlagHasParent)))
    return bad("bad square");
  const int32_t side = int32_t{1} << sideLog2;
  if (!std::isfinite(g.zBase) || !(g.zStep > 0) || !std::isfinite(g.zStep))
    return bad("bad height scale");
  if (clipX == 0 || clipY == 0 || clipX > side || clipY > side) return bad("bad data extent");
  const uint64_t gridPoints = uint64_t(side + 1) * uint64_t(side + 1);
  if (vertexCount < 3 || vertexCount > std::min<uint64_t>(gridPoints, kRtinMaxCount) ||
      triangleCount == 0 ||
      triangleCount > std::min<uint64_t>(2 * uint64_t(side) * side, kRtinMaxCount) ||
      decisionCount == 0 || decisionCount > 2 * uint64_t(kRtinMaxCount))
    return bad("bad vertex, triangle or decision count");
  if (uint64_t(kRtinHeaderBytes) + codedBytes != raw.size())
    return bad("coded size does not match the data");

  const bool hasParent = flags & kRtinFlagHasParent;
  auto models = std::make_unique<Models>();
  rc::Decoder coder(raw.subspan(kRtinHeaderBytes));
  uint32_t decided = 0;
  auto decide = [&](const BinTriangle&, int depth, bool walkInParent) -> Decision {
    if (decided++ == decisionCount) return {false};
    const bool inParent = depth == 0 ? hasParent && coder.bit(models->rootInParent) : walkInParent;
    const int context = std::min(depth, kRtinDepths - 1);
    const bool split = coder.bit(models->split[size_t(context * 2 + (inParent ? 1 : 0))]);
    const bool parentSplits = split && inParent && coder.bit(models->parentSplits[size_t(context)]);
    return {!coder.failed(), split, parentSplits};
  };
  Walk walk(side, vertexCount);
  walk.positions.reserve(vertexCount);
  walk.indices.reserve(3 * size_t(triangleCount));
  walk.splits.reserve(vertexCount);
  if (!walkChunk(sideLog2, flags & kRtinFlagRising, clipX, clipY, vertexCount, decide, walk) ||
      decided != decisionCount)
    return bad("split decisions do not match the chunk");
  if (walk.positions.size() != vertexCount || walk.indices.size() != 3 * size_t(triangleCount))
    return bad("split decisions do not give the stored counts");

  std::vector<ChunkVertex> vertices(vertexCount);
  for (size_t i = 0; i < vertexCount; ++i)
    vertices[i] = {uint16_t(walk.positions[i].x), uint16_t(walk.positions[i].y), 0, 0};
  Prediction previous{0, 0};
  for (const Coded& c : codingOrder(walk, side)) {
    const Prediction p = predict(c, vertices, previous);
    const int64_t zResidual = rc::decodeInteger(coder, models->z[size_t(c.context)]);
    const int64_t deltaResidual =
        rc::decodeInteger(coder, models->delta[size_t(c.context * 2 + (c.parentVertex ? 1 : 0))]);
    const int64_t z = p.z + zResidual;
    const int64_t target = p.target + zResidual + deltaResidual;
    const int64_t delta = target - z;
    if (coder.failed() || z < 0 || z > 65535 || delta < -32768 || delta > 32767)
      return bad("height out of range");
    ChunkVertex& v = vertices[c.vertex];
    v.z = uint16_t(z);
    v.morphDelta = int16_t(delta);
    previous = {int32_t(z), int32_t(target)};
  }
  if (!coder.exhausted()) return bad("coded data longer than the chunk");

  g.parts = splitChunkParts(vertices, std::move(walk.indices), {}, g.skirtSteps, uint16_t(side));
  const Status skirts = appendDerivedSkirts(g);
  if (!skirts) return bad(skirts.error().message);
  return g;
}

}  // namespace terralod
