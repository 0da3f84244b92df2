#include "terralod/format/vipm_chunk_codec.h"

#include <meshoptimizer.h>
#include <zstd.h>

#include <algorithm>
#include <bit>
#include <cassert>
#include <cmath>
#include <memory>
#include <mutex>

#include "terralod/format/byte_io.h"
#include "zstd_frame.h"

namespace terralod {
namespace {

static_assert(std::endian::native == std::endian::little, "terralod's format is little-endian");

constexpr uint32_t kVipmMagic = 0x50564C54;  // "TLVP"
constexpr size_t kVipmHeaderBytes = 48;
constexpr uint64_t kMaxDecodedBytes = uint64_t{1} << 24;
// Bytes per vertex: point, height, material (version 1: a u16 point; 2: a u32 point).
constexpr size_t kVertexBytesV1 = 5, kVertexBytesV2 = 7;

void pinIndexCodecVersion() {
  static std::once_flag once;
  std::call_once(once, [] { meshopt_encodeIndexVersion(1); });
}

template <typename T>
void putArray(ByteWriter& w, const std::vector<T>& values) {
  for (T v : values) w.put<T>(v);
}
template <typename T>
void getArray(ByteReader& r, std::vector<T>& values, size_t n) {
  values.resize(n);
  for (T& v : values) v = r.get<T>();
}

}  // namespace

uint16_t vipmChunkVersion(const VipmChunkData& c) {
  return c.width <= kVipmMaxGridPoints && c.height <= kVipmMaxGridPoints ? 1 : 2;
}

std::vector<uint8_t> encodeVipmChunk(const VipmChunkData& c, int compressionLevel) {
  pinIndexCodecVersion();
  const size_t n = c.vertexCount(), r = c.collapseCount();
  assert(c.heights.size() == n && c.materials.size() == n && c.errors.size() == r);
  assert(c.width <= kVipmMaxUpperGridPoints && c.height <= kVipmMaxUpperGridPoints);
  const uint16_t version = vipmChunkVersion(c);
  std::vector<uint8_t> stream(meshopt_encodeIndexBufferBound(c.indices.size(), n));
  stream.resize(
      meshopt_encodeIndexBuffer(stream.data(), stream.size(), c.indices.data(), c.indices.size()));
  const size_t vertexBytes = version == 1 ? kVertexBytesV1 : kVertexBytesV2;
  const size_t headerBytes = kVipmHeaderBytes + (version == 1 ? 0 : 4);
  std::vector<uint8_t> raw(headerBytes + vertexBytes * n + 4 * r + stream.size());
  ByteWriter w(raw.data());
  w.put<uint32_t>(kVipmMagic);
  w.put<uint16_t>(version);
  if (version == 1) {
    w.put<uint8_t>(uint8_t(c.width));
    w.put<uint8_t>(uint8_t(c.height));
  } else {
    w.put<uint16_t>(0);  // reserved
    w.put<uint16_t>(c.width);
    w.put<uint16_t>(c.height);
  }
  w.put<uint32_t>(uint32_t(n));
  w.put<uint32_t>(uint32_t(r));
  w.put<uint32_t>(c.triangleCount());
  w.put<uint32_t>(uint32_t(stream.size()));
  w.put<double>(c.zBase);
  w.put<double>(c.zStep);
  w.put<float>(c.errorStep);
  w.put<float>(c.finestError);
  if (version == 1) {
    for (uint32_t p : c.points) w.put<uint16_t>(uint16_t(p));
  } else {
    putArray(w, c.points);
  }
  putArray(w, c.heights);
  putArray(w, c.materials);
  putArray(w, c.targets);
  putArray(w, c.errors);
  w.putBytes(stream.data(), stream.size());
  assert(w.position() == raw.size());
  return zstdFrame(raw, compressionLevel);
}

Result<VipmChunkData> decodeVipmChunk(std::span<const uint8_t> blob, const std::string& subject) {
  auto bad = [&](const std::string& what) {
    return makeError(subject, "corrupt VIPM chunk: " + what);
  };
  const unsigned long long size = ZSTD_getFrameContentSize(blob.data(), blob.size());
  if (size == ZSTD_CONTENTSIZE_ERROR || size == ZSTD_CONTENTSIZE_UNKNOWN)
    return bad("not a zstd frame");
  if (size < kVipmHeaderBytes || size > kMaxDecodedBytes) return bad("implausible size");
  const auto buffer = std::make_unique_for_overwrite<uint8_t[]>(size);
  const size_t got = ZSTD_decompress(buffer.get(), size, blob.data(), blob.size());
  if (ZSTD_isError(got) || got != size) return bad("zstd data does not decompress");

  ByteReader r(buffer.get());
  if (r.get<uint32_t>() != kVipmMagic) return bad("wrong magic");
  const uint16_t version = r.get<uint16_t>();
  if (version != 1 && version != 2) return bad("unknown VIPM chunk version");
  const size_t headerBytes = kVipmHeaderBytes + (version == 1 ? 0 : 4);
  if (size < headerBytes) return bad("implausible size");
  VipmChunkData c;
  uint32_t largest = kVipmMaxGridPoints;
  if (version == 1) {
    c.width = r.get<uint8_t>();
    c.height = r.get<uint8_t>();
  } else {
    if (r.get<uint16_t>() != 0) return bad("reserved bytes are not zero");
    c.width = r.get<uint16_t>();
    c.height = r.get<uint16_t>();
    largest = kVipmMaxUpperGridPoints;
  }
  const uint32_t n = r.get<uint32_t>(), collapses = r.get<uint32_t>();
  const uint32_t triangles = r.get<uint32_t>(), streamBytes = r.get<uint32_t>();
  c.zBase = r.get<double>();
  c.zStep = r.get<double>();
  c.errorStep = r.get<float>();
  c.finestError = r.get<float>();
  if (c.width < 2 || c.width > largest || c.height < 2 || c.height > largest ||
      (version == 2 && vipmChunkVersion(c) == 1))
    return bad("bad grid size");
  const uint64_t points = uint64_t(c.width) * c.height;
  // Every vertex a u16 index (a node's own vertices, not its grid's points).
  if (n < 3 || n > points || n > 65536 || collapses > n - 3)
    return bad("bad vertex or collapse count");
  if (triangles == 0 || triangles > 2 * uint64_t(c.width - 1) * uint64_t(c.height - 1) ||
      triangles > 2 * uint64_t(n) || streamBytes < triangles)
    return bad("bad triangle count");
  if (!std::isfinite(c.zBase) || !(c.zStep > 0) || !std::isfinite(c.zStep))
    return bad("bad height scale");
  if (!(c.errorStep > 0) || !std::isfinite(c.errorStep) || !(c.finestError >= 0) ||
      !std::isfinite(c.finestError))
    return bad("bad error scale");
  const uint64_t vertexBytes = version == 1 ? kVertexBytesV1 : kVertexBytesV2;
  if (headerBytes + vertexBytes * n + 4 * uint64_t(collapses) + streamBytes != size)
    return bad("sizes do not match the data");
  if (version == 1) {
    c.points.resize(n);
    for (uint32_t& p : c.points) p = r.get<uint16_t>();
  } else {
    getArray(r, c.points, n);
  }
  getArray(r, c.heights, n);
  getArray(r, c.materials, n);
  getArray(r, c.targets, collapses);
  getArray(r, c.errors, collapses);
  std::vector<uint32_t> sorted(c.points);
  std::sort(sorted.begin(), sorted.end());
  if (sorted.back() >= points || std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end())
    return bad("bad vertex point");
  for (uint8_t m : c.materials)
    if (m >= 8) return bad("material out of range");
  for (uint32_t j = 0; j < collapses; ++j) {
    if (c.targets[j] >= n - 1 - j) return bad("collapse onto a removed vertex");
    if (j > 0 && c.errors[j] < c.errors[j - 1]) return bad("errors decrease");
  }
  c.indices.resize(size_t(triangles) * 3);
  if (meshopt_decodeIndexBuffer(c.indices.data(), c.indices.size(), sizeof(uint16_t),
                                buffer.get() + r.position(), streamBytes) != 0)
    return bad("index data does not decode");
  for (uint16_t i : c.indices)
    if (i >= n) return bad("index out of range");
  return c;
}

Result<TextureLayer> decodeVipmNormalMap(std::span<const uint8_t> texture, uint32_t chunkCells,
                                         const std::string& subject) {
  if (texture.empty()) return makeError(subject, "invalid texture: a VIPM chunk has no normal map");
  auto decoded = decodeTexture(texture, subject);
  if (!decoded) return decoded.error();
  const uint32_t size = vipmNormalMapCells(chunkCells) + 1;
  if (decoded->layers.size() != 1 || decoded->layers[0].kind != TextureLayerKind::kNormal ||
      decoded->layers[0].encoding != TextureEncoding::kBc5 || decoded->layers[0].size != size)
    return makeError(subject,
                     "invalid texture: a VIPM chunk's texture must be one BC5 normal "
                     "layer of " +
                         std::to_string(size) + " texels");
  return std::move(decoded->layers[0]);
}

}  // namespace terralod
