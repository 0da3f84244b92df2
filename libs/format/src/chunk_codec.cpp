#include "terralod/format/chunk_codec.h"

#include <meshoptimizer.h>
#include <zstd.h>

#include <bit>
#include <cassert>
#include <cmath>
#include <memory>
#include <mutex>
#include <span>

#include "terralod/format/byte_io.h"

namespace terralod {
namespace {

// Vertices and the blob's fields are copied to and from memory as they lie: little-endian.
static_assert(std::endian::native == std::endian::little, "terralod's format is little-endian");

constexpr uint32_t kChunkMagic = 0x42434C54;  // "TLCB"
constexpr uint16_t kChunkVersion = 1;
constexpr size_t kChunkHeaderBytes = 4 + 2 + 2 + 8 + 8;
constexpr size_t kPartHeaderBytes = 5 * 4;
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

}  // namespace

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

std::vector<uint8_t> encodeChunk(const ChunkGeometry& geometry, int compressionLevel) {
  pinCodecVersions();
  struct Encoded {
    std::vector<uint8_t> vertices, indices;
  };
  std::vector<Encoded> encoded(geometry.parts.size());
  size_t total = kChunkHeaderBytes + kPartHeaderBytes * geometry.parts.size();
  for (size_t p = 0; p < geometry.parts.size(); ++p) {
    const ChunkPart& part = geometry.parts[p];
    assert(part.vertices.size() <= 65536 && part.indices.size() % 3 == 0);
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
  w.put<uint16_t>(kChunkVersion);
  w.put<uint16_t>(static_cast<uint16_t>(geometry.parts.size()));
  w.put<double>(geometry.zBase);
  w.put<double>(geometry.zStep);
  for (size_t p = 0; p < geometry.parts.size(); ++p) {
    const ChunkPart& part = geometry.parts[p];
    w.put<uint32_t>(static_cast<uint32_t>(part.vertices.size()));
    w.put<uint32_t>(static_cast<uint32_t>(part.indices.size()));
    w.put<uint32_t>(part.surfaceIndexCount);
    w.put<uint32_t>(static_cast<uint32_t>(encoded[p].vertices.size()));
    w.put<uint32_t>(static_cast<uint32_t>(encoded[p].indices.size()));
  }
  for (const Encoded& e : encoded) {
    w.putBytes(e.vertices.data(), e.vertices.size());
    w.putBytes(e.indices.data(), e.indices.size());
  }
  std::vector<uint8_t> blob(ZSTD_compressBound(raw.size()));
  const size_t n =
      ZSTD_compress(blob.data(), blob.size(), raw.data(), raw.size(), compressionLevel);
  assert(!ZSTD_isError(n));
  blob.resize(n);
  return blob;
}

Result<ChunkGeometry> decodeChunk(std::span<const uint8_t> blob, const std::string& subject) {
  auto bad = [&](const std::string& what) { return makeError(subject, "corrupt chunk: " + what); };
  const unsigned long long size = ZSTD_getFrameContentSize(blob.data(), blob.size());
  if (size == ZSTD_CONTENTSIZE_ERROR || size == ZSTD_CONTENTSIZE_UNKNOWN)
    return bad("not a zstd frame");
  if (size < kChunkHeaderBytes || size > kMaxDecodedBytes) return bad("implausible size");
  // Not zero-filled: zstd writes every byte of a frame that decodes, and a corrupt frame that
  // claims a huge size then costs address space, not 256 MiB of zeroed pages.
  const auto buffer = std::make_unique_for_overwrite<uint8_t[]>(size);
  const std::span<const uint8_t> raw(buffer.get(), size);
  const size_t got = ZSTD_decompress(buffer.get(), size, blob.data(), blob.size());
  if (ZSTD_isError(got) || got != size) return bad("zstd data does not decompress");

  ByteReader r(raw.data());
  if (r.get<uint32_t>() != kChunkMagic) return bad("wrong magic");
  if (r.get<uint16_t>() != kChunkVersion) return bad("unknown chunk version");
  const uint16_t partCount = r.get<uint16_t>();
  ChunkGeometry g;
  g.zBase = r.get<double>();
  g.zStep = r.get<double>();
  if (!std::isfinite(g.zBase) || !(g.zStep > 0) || !std::isfinite(g.zStep))
    return bad("bad height scale");
  if (partCount == 0 || kChunkHeaderBytes + size_t(partCount) * kPartHeaderBytes > raw.size())
    return bad("bad part count");
  struct PartHeader {
    uint32_t vertexCount, indexCount, surfaceIndexCount, vertexBytes, indexBytes;
  };
  std::vector<PartHeader> headers(partCount);
  uint64_t payload = 0;
  for (PartHeader& ph : headers) {
    ph = {r.get<uint32_t>(), r.get<uint32_t>(), r.get<uint32_t>(), r.get<uint32_t>(),
          r.get<uint32_t>()};
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
  return g;
}

}  // namespace terralod
