#include "terralod/format/chunk_codec.h"

#include <meshoptimizer.h>
#include <zstd.h>

#include <algorithm>
#include <bit>
#include <cassert>
#include <cmath>
#include <cstdint>
#include <memory>
#include <mutex>
#include <span>
#include <unordered_map>

#include "terralod/format/byte_io.h"
#include "terralod/format/rtin_chunk_codec.h"
#include "zstd_frame.h"

namespace terralod {
namespace {

// Vertices and the blob's fields are copied to and from memory as they lie: little-endian.
static_assert(std::endian::native == std::endian::little, "terralod's format is little-endian");

constexpr uint32_t kChunkMagic = 0x42434C54;  // "TLCB"
// The payload's fixed header and a part's header, by payload version (docs/format.md).
constexpr size_t kHeaderBytesV1 = 4 + 2 + 2 + 8 + 8;      // ... zBase f64, zStep f64
constexpr size_t kHeaderBytesV2 = 4 + 2 + 2 + 8 + 4 + 8;  // ... zStep f64, zBase i32 steps, skirts
constexpr size_t kPartHeaderBytesV1 = 5 * 4;
constexpr size_t kPartHeaderBytesV2 = 4 * 4;  // no surfaceIndexCount: every index is surface
constexpr uint64_t kMaxDecodedBytes = uint64_t{1} << 28;

// The frozen format pins the codec versions; newer meshoptimizer releases still decode them.
// The setting is meshoptimizer's process-wide state: nothing else in terralod may change it.
void pinCodecVersions() {
  static std::once_flag once;
  std::call_once(once, [] {
    meshopt_encodeVertexVersion(0);
    meshopt_encodeIndexVersion(1);
  });
}

// The largest x and y of the chunk's vertices: where its north and east sides lie.
std::array<uint16_t, 2> extentOf(const ChunkGeometry& g) {
  std::array<uint16_t, 2> extent{};
  for (const ChunkPart& part : g.parts)
    for (const ChunkVertex& v : part.vertices)
      extent = {std::max(extent[0], v.x), std::max(extent[1], v.y)};
  return extent;
}

}  // namespace

std::vector<SkirtEdge> skirtEdges(const ChunkPart& part, const std::array<uint16_t, 4>& skirtSteps,
                                  uint16_t extentX, uint16_t extentY) {
  // The line of each side: the coordinate (x for east and west, y for south and north) and
  // its value.
  const std::array<uint16_t, 4> line = {0, extentX, extentY, 0};
  auto coordinate = [](const ChunkVertex& v, int side) {
    return (side == kSideEast || side == kSideWest) ? v.x : v.y;
  };
  auto alongOf = [](const ChunkVertex& v, int side) {
    return (side == kSideEast || side == kSideWest) ? v.y : v.x;
  };
  std::vector<SkirtEdge> edges;
  for (size_t t = 0; t < part.surfaceIndexCount; t += 3) {
    const uint32_t* tri = &part.indices[t];
    for (int side = 0; side < 4; ++side) {
      if (skirtSteps[size_t(side)] == 0) continue;
      bool on[3];
      for (int k = 0; k < 3; ++k)
        on[k] = coordinate(part.vertices[tri[k]], side) == line[size_t(side)];
      if (on[0] && on[1] && on[2]) continue;  // degenerate: no inside to hang a skirt from
      for (int k = 0; k < 3; ++k) {
        if (!on[k] || !on[(k + 1) % 3]) continue;
        const uint32_t p = tri[k], q = tri[(k + 1) % 3];
        const uint16_t along =
            std::min(alongOf(part.vertices[p], side), alongOf(part.vertices[q], side));
        edges.push_back({uint8_t(side), along, p, q});
      }
    }
  }
  std::sort(edges.begin(), edges.end(), [](const SkirtEdge& a, const SkirtEdge& b) {
    return a.side != b.side ? a.side < b.side : a.along < b.along;
  });
  return edges;
}

Status appendDerivedSkirts(ChunkGeometry& g) {
  const auto [extentX, extentY] = extentOf(g);
  for (ChunkPart& part : g.parts) {
    const std::vector<SkirtEdge> edges = skirtEdges(part, g.skirtSteps, extentX, extentY);
    if (edges.empty()) continue;
    // The bottom of each (vertex, side), appended in the order the side's edges come.
    std::vector<uint32_t> bottomOf;
    int bottomSide = -1;
    auto bottom = [&](uint32_t top, int side) -> Result<uint32_t> {
      if (side != bottomSide) {
        bottomOf.assign(part.vertices.size(), ~0u);
        bottomSide = side;
      }
      if (bottomOf[top] != ~0u) return bottomOf[top];
      ChunkVertex v = part.vertices[top];
      const uint16_t steps = g.skirtSteps[size_t(side)];
      if (v.z < steps) return Error{"skirt reaches below the height range"};
      if (part.vertices.size() >= 65536) return Error{"too many vertices with its skirts"};
      v.z = uint16_t(v.z - steps);
      bottomOf[top] = uint32_t(part.vertices.size());
      part.vertices.push_back(v);
      return bottomOf[top];
    };
    part.indices.resize(part.surfaceIndexCount);
    for (const SkirtEdge& e : edges) {
      // Ends in increasing coordinate along the side, so bottoms come in that order.
      const bool pFirst = [&] {
        const ChunkVertex &a = part.vertices[e.p], &b = part.vertices[e.q];
        return (e.side == kSideEast || e.side == kSideWest) ? a.y < b.y : a.x < b.x;
      }();
      auto first = bottom(pFirst ? e.p : e.q, e.side);
      if (!first) return first.error();
      auto second = bottom(pFirst ? e.q : e.p, e.side);
      if (!second) return second.error();
      const uint32_t p2 = pFirst ? *first : *second, q2 = pFirst ? *second : *first;
      // Outwards (counter-clockwise seen from outside the chunk), split as version 1 splits
      // them: along the diagonal from the side's lower end on the south and east sides...
      if (e.side == kSideSouth || e.side == kSideEast)
        part.indices.insert(part.indices.end(), {e.p, p2, q2, e.p, q2, e.q});
      else  // ...and from its lower end, q, on the north and west sides
        part.indices.insert(part.indices.end(), {e.q, p2, q2, e.q, e.p, p2});
    }
    if (part.indices.size() > (1u << 24)) return Error{"too many indices with its skirts"};
  }
  return {};
}

namespace {

constexpr size_t kPartVertexLimit = 65535;

// Skirt bottoms a reader derives for these surface triangles (payload version 2 and 3): one
// per vertex and skirted side, over the edges along that side.
// `slot` is scratch, one entry per vertex, ~0u on entry and on return.
size_t derivedBottoms(const std::vector<ChunkVertex>& vertices,
                      const std::vector<uint32_t>& surface,
                      const std::array<uint16_t, 4>& skirtSteps, uint16_t side,
                      std::vector<uint32_t>& slot) {
  if (skirtSteps == std::array<uint16_t, 4>{}) return 0;
  ChunkPart part;
  std::vector<uint32_t> used;
  for (uint32_t i : surface) {
    if (slot[i] == ~0u) {
      slot[i] = uint32_t(part.vertices.size());
      part.vertices.push_back(vertices[i]);
      used.push_back(i);
    }
    part.indices.push_back(slot[i]);
  }
  for (uint32_t i : used) slot[i] = ~0u;
  part.surfaceIndexCount = uint32_t(part.indices.size());
  // The extents a reader finds: the chunk's side wherever a side has a skirt (its footprint is
  // clipped only along the data's boundary, which has none).
  std::vector<uint64_t> keys;
  for (const SkirtEdge& e : skirtEdges(part, skirtSteps, side, side))
    keys.insert(keys.end(), {uint64_t(e.p) * 4 + e.side, uint64_t(e.q) * 4 + e.side});
  std::sort(keys.begin(), keys.end());
  return size_t(std::unique(keys.begin(), keys.end()) - keys.begin());
}

void splitParts(const std::vector<ChunkVertex>& vertices, const std::array<uint16_t, 4>& steps,
                uint16_t chunkSide, std::vector<uint32_t> surface, std::vector<uint32_t> skirt,
                double x0, double y0, double side, std::vector<uint32_t>& slot,
                std::vector<ChunkPart>& parts) {
  // The distinct vertices used, in increasing order.
  std::vector<uint32_t> order;
  for (const auto* list : {&surface, &skirt})
    for (uint32_t i : *list)
      if (slot[i] == ~0u) {
        slot[i] = 0;
        order.push_back(i);
      }
  for (uint32_t i : order) slot[i] = ~0u;
  // The bottoms a reader derives count only where they could tip the balance (at most c + 1
  // a side).
  const size_t bottomsAtMost = 4 * (size_t(chunkSide) + 1);
  const bool fits = order.size() <= kPartVertexLimit &&
                    (order.size() + bottomsAtMost <= kPartVertexLimit ||
                     order.size() + derivedBottoms(vertices, surface, steps, chunkSide, slot) <=
                         kPartVertexLimit);
  if (fits || side <= 1) {
    std::sort(order.begin(), order.end());
    ChunkPart part;
    part.vertices.reserve(order.size());
    for (uint32_t from : order) {
      slot[from] = static_cast<uint32_t>(part.vertices.size());
      part.vertices.push_back(vertices[from]);
    }
    part.indices.reserve(surface.size() + skirt.size());
    for (uint32_t i : surface) part.indices.push_back(slot[i]);
    part.surfaceIndexCount = static_cast<uint32_t>(part.indices.size());
    for (uint32_t i : skirt) part.indices.push_back(slot[i]);
    for (uint32_t i : order) slot[i] = ~0u;
    if (!part.indices.empty()) parts.push_back(std::move(part));
    return;
  }
  const double half = side / 2;
  std::vector<uint32_t> qs[4], qk[4];
  auto quadrant = [&](const uint32_t* tri) {
    double cx = 0, cy = 0;
    for (int k = 0; k < 3; ++k) cx += vertices[tri[k]].x, cy += vertices[tri[k]].y;
    return (cx / 3 >= x0 + half ? 1 : 0) + (cy / 3 >= y0 + half ? 2 : 0);
  };
  for (size_t t = 0; t < surface.size(); t += 3) {
    auto& q = qs[quadrant(&surface[t])];
    q.insert(q.end(), surface.begin() + t, surface.begin() + t + 3);
  }
  for (size_t t = 0; t < skirt.size(); t += 3) {
    auto& q = qk[quadrant(&skirt[t])];
    q.insert(q.end(), skirt.begin() + t, skirt.begin() + t + 3);
  }
  for (int q = 0; q < 4; ++q)
    splitParts(vertices, steps, chunkSide, std::move(qs[q]), std::move(qk[q]), x0 + (q & 1) * half,
               y0 + (q >> 1) * half, half, slot, parts);
}

}  // namespace

std::vector<ChunkPart> splitChunkParts(const std::vector<ChunkVertex>& vertices,
                                       std::vector<uint32_t> surface, std::vector<uint32_t> skirt,
                                       const std::array<uint16_t, 4>& derivedSkirtSteps,
                                       uint16_t side) {
  std::vector<ChunkPart> parts;
  // Every vertex used and room for any skirts (at most side + 1 bottoms a side): one part,
  // as the recursion would make it, without counting.
  if (vertices.size() + 4 * (size_t(side) + 1) <= kPartVertexLimit) {
    std::vector<uint8_t> used(vertices.size(), 0);
    for (uint32_t i : surface) used[i] = 1;
    for (uint32_t i : skirt) used[i] = 1;
    if (std::find(used.begin(), used.end(), 0) == used.end()) {
      ChunkPart& part = parts.emplace_back();
      part.vertices = vertices;
      part.surfaceIndexCount = uint32_t(surface.size());
      part.indices = std::move(surface);
      part.indices.insert(part.indices.end(), skirt.begin(), skirt.end());
      if (part.indices.empty()) parts.clear();
      return parts;
    }
  }
  std::vector<uint32_t> slot(vertices.size(), ~0u);
  splitParts(vertices, derivedSkirtSteps, side, std::move(surface), std::move(skirt), 0, 0, side,
             slot, parts);
  return parts;
}

void optimizeChunkPart(ChunkPart& part) {
  const size_t vertexCount = part.vertices.size();
  std::vector<uint32_t> ordered(part.indices.size());
  const size_t surface = part.surfaceIndexCount;
  meshopt_optimizeVertexCache(ordered.data(), part.indices.data(), surface, vertexCount);
  meshopt_optimizeVertexCache(ordered.data() + surface, part.indices.data() + surface,
                              part.indices.size() - surface, vertexCount);
  std::vector<ChunkVertex> vertices(vertexCount);
  const size_t used =
      meshopt_optimizeVertexFetch(vertices.data(), ordered.data(), ordered.size(),
                                  part.vertices.data(), vertexCount, sizeof(ChunkVertex));
  vertices.resize(used);
  part.vertices = std::move(vertices);
  part.indices = std::move(ordered);
}

std::vector<uint8_t> encodeChunk(const ChunkGeometry& geometry, int compressionLevel,
                                 ChunkPayloadVersion payload) {
  pinCodecVersions();
  assert(payload != ChunkPayloadVersion::kRtinCoded);  // encodeRtinChunk writes those
  const bool derived = payload == ChunkPayloadVersion::kDerivedSkirts;
  struct Encoded {
    std::vector<uint8_t> vertices, indices;
  };
  std::vector<Encoded> encoded(geometry.parts.size());
  size_t total = derived ? kHeaderBytesV2 + kPartHeaderBytesV2 * geometry.parts.size()
                         : kHeaderBytesV1 + kPartHeaderBytesV1 * geometry.parts.size();
  for (size_t p = 0; p < geometry.parts.size(); ++p) {
    const ChunkPart& part = geometry.parts[p];
    assert(part.vertices.size() <= 65536 && part.indices.size() % 3 == 0);
    assert(!derived || part.surfaceIndexCount == part.indices.size());
    Encoded& e = encoded[p];
    e.vertices.resize(meshopt_encodeVertexBufferBound(part.vertices.size(), sizeof(ChunkVertex)));
    e.vertices.resize(meshopt_encodeVertexBuffer(e.vertices.data(), e.vertices.size(),
                                                 part.vertices.data(), part.vertices.size(),
                                                 sizeof(ChunkVertex)));
    e.indices.resize(meshopt_encodeIndexBufferBound(part.indices.size(), part.vertices.size()));
    e.indices.resize(meshopt_encodeIndexBuffer(e.indices.data(), e.indices.size(),
                                               part.indices.data(), part.indices.size()));
    total += e.vertices.size() + e.indices.size();
  }
  std::vector<uint8_t> raw(total);
  ByteWriter w(raw.data());
  w.put<uint32_t>(kChunkMagic);
  w.put<uint16_t>(static_cast<uint16_t>(payload));
  w.put<uint16_t>(static_cast<uint16_t>(geometry.parts.size()));
  if (derived) {
    // zBase is a whole number of steps (the builder rounds heights on the level's grid).
    const double baseSteps = std::round(geometry.zBase / geometry.zStep);
    assert(baseSteps >= INT32_MIN && baseSteps <= INT32_MAX &&
           baseSteps * geometry.zStep == geometry.zBase);
    w.put<double>(geometry.zStep);
    w.put<int32_t>(static_cast<int32_t>(baseSteps));
    for (uint16_t steps : geometry.skirtSteps) w.put<uint16_t>(steps);
  } else {
    w.put<double>(geometry.zBase);
    w.put<double>(geometry.zStep);
  }
  for (size_t p = 0; p < geometry.parts.size(); ++p) {
    const ChunkPart& part = geometry.parts[p];
    w.put<uint32_t>(static_cast<uint32_t>(part.vertices.size()));
    w.put<uint32_t>(static_cast<uint32_t>(part.indices.size()));
    if (!derived) w.put<uint32_t>(part.surfaceIndexCount);
    w.put<uint32_t>(static_cast<uint32_t>(encoded[p].vertices.size()));
    w.put<uint32_t>(static_cast<uint32_t>(encoded[p].indices.size()));
  }
  for (const Encoded& e : encoded) {
    w.putBytes(e.vertices.data(), e.vertices.size());
    w.putBytes(e.indices.data(), e.indices.size());
  }
  return zstdFrame(raw, compressionLevel);
}

Result<ChunkGeometry> decodeChunk(std::span<const uint8_t> blob, const std::string& subject) {
  auto bad = [&](const std::string& what) { return makeError(subject, "corrupt chunk: " + what); };
  const unsigned long long size = ZSTD_getFrameContentSize(blob.data(), blob.size());
  if (size == ZSTD_CONTENTSIZE_ERROR || size == ZSTD_CONTENTSIZE_UNKNOWN)
    return bad("not a zstd frame");
  if (size < kHeaderBytesV1 || size > kMaxDecodedBytes) return bad("implausible size");
  // Not zero-filled: zstd writes every byte of a frame that decodes, and a corrupt frame that
  // claims a huge size then costs address space, not 256 MiB of zeroed pages.
  const auto buffer = std::make_unique_for_overwrite<uint8_t[]>(size);
  const std::span<const uint8_t> raw(buffer.get(), size);
  const size_t got = ZSTD_decompress(buffer.get(), size, blob.data(), blob.size());
  if (ZSTD_isError(got) || got != size) return bad("zstd data does not decompress");

  ByteReader r(raw.data());
  if (r.get<uint32_t>() != kChunkMagic) return bad("wrong magic");
  const uint16_t version = r.get<uint16_t>();
  if (version == uint16_t(ChunkPayloadVersion::kRtinCoded)) return decodeRtinPayload(raw, subject);
  if (version != uint16_t(ChunkPayloadVersion::kStoredSkirts) &&
      version != uint16_t(ChunkPayloadVersion::kDerivedSkirts))
    return bad("unknown chunk version");
  const bool derived = version == uint16_t(ChunkPayloadVersion::kDerivedSkirts);
  const size_t headerBytes = derived ? kHeaderBytesV2 : kHeaderBytesV1;
  const size_t partHeaderBytes = derived ? kPartHeaderBytesV2 : kPartHeaderBytesV1;
  if (raw.size() < headerBytes) return bad("implausible size");
  const uint16_t partCount = r.get<uint16_t>();
  ChunkGeometry g;
  if (derived) {
    g.zStep = r.get<double>();
    g.zBase = r.get<int32_t>() * g.zStep;
    for (uint16_t& steps : g.skirtSteps) steps = r.get<uint16_t>();
  } else {
    g.zBase = r.get<double>();
    g.zStep = r.get<double>();
  }
  if (!std::isfinite(g.zBase) || !(g.zStep > 0) || !std::isfinite(g.zStep))
    return bad("bad height scale");
  if (partCount == 0 || headerBytes + size_t(partCount) * partHeaderBytes > raw.size())
    return bad("bad part count");
  struct PartHeader {
    uint32_t vertexCount, indexCount, surfaceIndexCount, vertexBytes, indexBytes;
  };
  std::vector<PartHeader> headers(partCount);
  uint64_t payload = 0;
  for (PartHeader& ph : headers) {
    ph.vertexCount = r.get<uint32_t>();
    ph.indexCount = r.get<uint32_t>();
    ph.surfaceIndexCount = derived ? ph.indexCount : r.get<uint32_t>();
    ph.vertexBytes = r.get<uint32_t>();
    ph.indexBytes = r.get<uint32_t>();
    // meshoptimizer's index codec spends at least a byte per triangle: a count its stream
    // cannot hold is refused before anything is allocated for it.
    if (ph.vertexCount == 0 || ph.vertexCount > 65536 || ph.indexCount % 3 != 0 ||
        ph.surfaceIndexCount % 3 != 0 || ph.surfaceIndexCount > ph.indexCount ||
        ph.indexCount > (1u << 24) || ph.indexBytes < ph.indexCount / 3)
      return bad("bad part header");
    payload += uint64_t(ph.vertexBytes) + ph.indexBytes;
  }
  if (r.position() + payload != raw.size()) return bad("part sizes do not match the data");
  g.parts.resize(partCount);
  for (size_t p = 0; p < partCount; ++p) {
    const PartHeader& ph = headers[p];
    ChunkPart& part = g.parts[p];
    part.vertices.resize(ph.vertexCount);
    part.indices.resize(ph.indexCount);
    part.surfaceIndexCount = ph.surfaceIndexCount;
    const uint8_t* data = raw.data() + r.position();
    if (meshopt_decodeVertexBuffer(part.vertices.data(), ph.vertexCount, sizeof(ChunkVertex), data,
                                   ph.vertexBytes) != 0)
      return bad("vertex data does not decode");
    r.seek(r.position() + ph.vertexBytes);
    data = raw.data() + r.position();
    if (ph.indexCount > 0 && meshopt_decodeIndexBuffer(part.indices.data(), ph.indexCount,
                                                       sizeof(uint32_t), data, ph.indexBytes) != 0)
      return bad("index data does not decode");
    r.seek(r.position() + ph.indexBytes);
    for (uint32_t index : part.indices)
      if (index >= ph.vertexCount) return bad("index out of range");
  }
  if (derived) {
    const Status skirts = appendDerivedSkirts(g);
    if (!skirts) return bad(skirts.error().message);
  }
  return g;
}

}  // namespace terralod
