// The LDI blob of a .tlv file (docs/format.md, "Vegetation files", "LDI blobs") and the
// octahedral splat normals.
//
// A blob is an 80-byte header (the camera and the counts) and one zstd frame holding byte
// planes: the layer counts, then for all depth pixels each colour channel, the depth as three
// planes of zigzagged differences and the splat index as its octahedral row and column.
// Planes put alike bytes together (alpha is nearly always 255, the high depth bytes and the
// splat rows change slowly): on synthetic LDIs with varying colours they compress to 5.1 bytes
// a depth pixel where the 8-byte pixels as they are in memory take 7.1 (docs/format.md).

#include <zstd.h>

#include <algorithm>
#include <bit>
#include <cassert>
#include <cmath>
#include <cstring>
#include <memory>
#include <string>

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>

#include "terralod/format/byte_io.h"
#include "terralod/vegetation/ldi.h"

namespace terralod::veg {
namespace {

static_assert(std::endian::native == std::endian::little, "terralod's format is little-endian");

constexpr uint8_t kLdiMagic[4] = {'T', 'L', 'D', 'I'};
constexpr uint32_t kLdiVersion = 1;
constexpr size_t kLdiHeaderBytes = 80;
constexpr uint32_t kLdiMaxSide = 4096;
// A payload is at most 256 MiB: far beyond any LDI a bake makes (the finest of the paper's
// are 468 pixels across) and small enough to allocate before decompressing.
constexpr uint64_t kLdiMaxPayloadBytes = uint64_t{1} << 28;
// Bytes per depth pixel in the payload: r, g, b, a, three depth bytes, splat row and column.
constexpr uint64_t kPlaneCount = 9;
// zstd level for LDI payloads: 9 encodes a 500 × 252 LDI of 336 k depth pixels in 0.04 s;
// 19 saves 4–9 % more but takes 0.7 s, and levels 12 and 15 gain nothing over 9.
constexpr int kLdiZstdLevel = 9;
// No zstd block expands more than 128 KiB from fewer than 4 bytes (an RLE block), so a frame
// promising more than this many times its own size is a lie, refused before allocating.
constexpr uint64_t kZstdMaxRatio = 32768;

// Octahedral grid for splat normals: 45 × 45 cells over the unfolded octahedron [-1, 1]².
constexpr int kSplatGrid = 45;
static_assert(kSplatGrid * kSplatGrid - 1 == kLdiMaxSplatCode);

float signNotZero(float v) {
  return v < 0 ? -1.0f : 1.0f;
}

glm::vec2 octahedralFromUnit(glm::vec3 n) {
  n /= std::abs(n.x) + std::abs(n.y) + std::abs(n.z);
  glm::vec2 p(n.x, n.y);
  if (n.z < 0)
    p = glm::vec2((1 - std::abs(n.y)) * signNotZero(n.x), (1 - std::abs(n.x)) * signNotZero(n.y));
  return p;
}

glm::vec3 unitFromOctahedral(glm::vec2 p) {
  glm::vec3 n(p.x, p.y, 1 - std::abs(p.x) - std::abs(p.y));
  if (n.z < 0)
    n = glm::vec3((1 - std::abs(p.y)) * signNotZero(p.x), (1 - std::abs(p.x)) * signNotZero(p.y),
                  n.z);
  return glm::normalize(n);
}

// Written so that the middle cell's centre is exactly (0, 0): straight up decodes exactly.
glm::vec3 cellCentreNormal(int row, int col) {
  const auto centre = [](int i) { return float(2 * i + 1 - kSplatGrid) / kSplatGrid; };
  return unitFromOctahedral(glm::vec2(centre(col), centre(row)));
}

// Depths are coded as differences from the depth before them in the same plane order: the
// previous layer of the pixel, or for a first layer the first layer of the last pixel that had
// one (neighbouring pixels mostly see the same surface). Differences wrap modulo 2^20 and are
// zigzagged so that small steps either way have small codes.
uint32_t zigzag20(uint32_t depth, uint32_t previous) {
  const int32_t d = int32_t((depth - previous) << 12) >> 12;  // signed 20-bit difference
  return (uint32_t(d) << 1 ^ uint32_t(d >> 31)) & kLdiMaxDepth;
}
uint32_t unzigzag20(uint32_t code, uint32_t previous) {
  const uint32_t d = (code >> 1) ^ (0u - (code & 1));
  return (previous + d) & kLdiMaxDepth;
}

class PlaneWriter {
 public:
  PlaneWriter(uint8_t* planes, uint64_t count) : mPlanes(planes), mCount(count) {}
  void put(uint64_t plane, uint64_t i, uint8_t v) { mPlanes[plane * mCount + i] = v; }

 private:
  uint8_t* mPlanes;
  uint64_t mCount;
};

Error corrupt(const std::string& problem) {
  return Error{"corrupt LDI: " + problem};
}

bool finite(float v) {
  return std::isfinite(v);
}
bool finite(const glm::vec3& v) {
  return finite(v.x) && finite(v.y) && finite(v.z);
}

}  // namespace

uint32_t encodeSplatNormal(const glm::vec3& unitNormal) {
  const float length = glm::length(unitNormal);
  if (!(length > 0) || !std::isfinite(length)) return (kSplatGrid / 2) * (kSplatGrid + 1);
  const glm::vec3 n = unitNormal / length;
  const glm::vec2 p = octahedralFromUnit(n);
  const auto cell = [](float v) {
    return std::clamp(int(std::floor((v + 1) * 0.5f * kSplatGrid)), 0, kSplatGrid - 1);
  };
  // The cell holding the point is not always the one whose centre is nearest in angle (the
  // octahedral map stretches cells unevenly), so its neighbours are tried too.
  const int row0 = cell(p.y), col0 = cell(p.x);
  int bestRow = row0, bestCol = col0;
  float bestDot = -2;
  for (int row = std::max(0, row0 - 1); row <= std::min(kSplatGrid - 1, row0 + 1); ++row)
    for (int col = std::max(0, col0 - 1); col <= std::min(kSplatGrid - 1, col0 + 1); ++col) {
      const float d = glm::dot(cellCentreNormal(row, col), n);
      if (d > bestDot) bestDot = d, bestRow = row, bestCol = col;
    }
  return uint32_t(bestRow * kSplatGrid + bestCol);
}

glm::vec3 decodeSplatNormal(uint32_t splat) {
  assert(splat <= kLdiMaxSplatCode);
  if (splat > kLdiMaxSplatCode) return glm::vec3(0, 0, 1);
  return cellCentreNormal(int(splat / kSplatGrid), int(splat % kSplatGrid));
}

std::vector<uint8_t> encodeLdi(const Ldi& ldi) {
  const LdiCamera& c = ldi.camera;
  const uint64_t pixelCount = uint64_t(c.width) * c.height;
  const uint64_t n = ldi.pixels.size();
  assert(c.width >= 1 && c.width <= kLdiMaxSide && c.height >= 1 && c.height <= kLdiMaxSide);
  assert(ldi.layerCounts.size() == pixelCount);
  const uint64_t payloadBytes = pixelCount + kPlaneCount * n;
  assert(payloadBytes <= kLdiMaxPayloadBytes);

  std::vector<uint8_t> payload(payloadBytes);
  std::copy(ldi.layerCounts.begin(), ldi.layerCounts.end(), payload.begin());
  PlaneWriter planes(payload.data() + pixelCount, n);
  uint64_t i = 0;
  uint32_t lastFirstDepth = 0;
  for (uint64_t p = 0; p < pixelCount; ++p) {
    uint32_t previous = lastFirstDepth;
    for (uint32_t layer = 0; layer < ldi.layerCounts[p]; ++layer, ++i) {
      assert(i < n);
      const DepthPixel& px = ldi.pixels[i];
      assert((px.zsplat >> 31) == 0 && px.splat() <= kLdiMaxSplatCode);
      for (uint64_t channel = 0; channel < 4; ++channel)
        planes.put(channel, i, uint8_t(px.rgba >> (8 * channel)));
      const uint32_t code = zigzag20(px.depth(), previous);
      planes.put(4, i, uint8_t(code >> 16));
      planes.put(5, i, uint8_t(code >> 8));
      planes.put(6, i, uint8_t(code));
      planes.put(7, i, uint8_t(px.splat() / kSplatGrid));
      planes.put(8, i, uint8_t(px.splat() % kSplatGrid));
      previous = px.depth();
      if (layer == 0) lastFirstDepth = px.depth();
    }
  }
  assert(i == n);

  std::vector<uint8_t> blob(kLdiHeaderBytes + ZSTD_compressBound(payload.size()));
  ByteWriter h(blob.data());
  h.putBytes(kLdiMagic, 4);
  h.put<uint32_t>(kLdiVersion);
  h.put<uint32_t>(c.width);
  h.put<uint32_t>(c.height);
  h.put<uint32_t>(uint32_t(n));
  h.put<float>(c.pixelSize);
  for (const glm::vec3* v : {&c.origin, &c.axisU, &c.axisV, &c.direction})
    for (int k = 0; k < 3; ++k) h.put<float>((*v)[k]);
  h.put<float>(c.depthMin);
  h.put<float>(c.depthMax);
  assert(h.position() == kLdiHeaderBytes);

  thread_local std::unique_ptr<ZSTD_CCtx, size_t (*)(ZSTD_CCtx*)> context(ZSTD_createCCtx(),
                                                                          ZSTD_freeCCtx);
  const size_t compressed =
      ZSTD_compressCCtx(context.get(), blob.data() + kLdiHeaderBytes, blob.size() - kLdiHeaderBytes,
                        payload.data(), payload.size(), kLdiZstdLevel);
  assert(!ZSTD_isError(compressed));
  blob.resize(kLdiHeaderBytes + compressed);
  return blob;
}

Result<Ldi> decodeLdi(const uint8_t* data, size_t size) {
  if (size < kLdiHeaderBytes)
    return corrupt("blob of " + std::to_string(size) + " bytes is shorter than its " +
                   std::to_string(kLdiHeaderBytes) + "-byte header");
  if (std::memcmp(data, kLdiMagic, 4) != 0) return corrupt("bad magic");
  ByteReader h(data + 4);
  if (const uint32_t version = h.get<uint32_t>(); version != kLdiVersion)
    return corrupt("version " + std::to_string(version) + " is not supported (this reads 1)");

  Ldi ldi;
  LdiCamera& c = ldi.camera;
  c.width = h.get<uint32_t>();
  c.height = h.get<uint32_t>();
  const uint64_t n = h.get<uint32_t>();
  if (c.width < 1 || c.width > kLdiMaxSide || c.height < 1 || c.height > kLdiMaxSide)
    return corrupt("size " + std::to_string(c.width) + " x " + std::to_string(c.height) +
                   " is outside 1..4096 pixels");
  c.pixelSize = h.get<float>();
  for (glm::vec3* v : {&c.origin, &c.axisU, &c.axisV, &c.direction})
    for (int k = 0; k < 3; ++k) (*v)[k] = h.get<float>();
  c.depthMin = h.get<float>();
  c.depthMax = h.get<float>();
  if (!finite(c.pixelSize) || !(c.pixelSize > 0)) return corrupt("pixel size is not positive");
  if (!finite(c.origin) || !finite(c.axisU) || !finite(c.axisV) || !finite(c.direction))
    return corrupt("camera position or axes are not finite");
  if (!finite(c.depthMin) || !finite(c.depthMax) || !finite(c.depthMax - c.depthMin) ||
      !(c.depthMax > c.depthMin))
    return corrupt("depth range is empty or not finite");

  const uint64_t pixelCount = uint64_t(c.width) * c.height;
  const uint64_t payloadBytes = pixelCount + kPlaneCount * n;
  if (payloadBytes > kLdiMaxPayloadBytes)
    return corrupt(std::to_string(n) + " depth pixels are more than an LDI may hold");
  if (n > 255 * pixelCount)
    return corrupt(std::to_string(n) + " depth pixels cannot fit in " + std::to_string(pixelCount) +
                   " pixels of at most 255 layers");

  const uint8_t* frame = data + kLdiHeaderBytes;
  const size_t frameBytes = size - kLdiHeaderBytes;
  const size_t frameLength = ZSTD_findFrameCompressedSize(frame, frameBytes);
  if (ZSTD_isError(frameLength)) return corrupt("payload is not a zstd frame");
  if (frameLength != frameBytes)
    return corrupt(std::to_string(frameBytes - frameLength) + " bytes follow the zstd frame");
  const unsigned long long promised = ZSTD_getFrameContentSize(frame, frameBytes);
  if (promised == ZSTD_CONTENTSIZE_ERROR || promised == ZSTD_CONTENTSIZE_UNKNOWN)
    return corrupt("zstd frame does not record its size");
  if (promised != payloadBytes)
    return corrupt("payload is " + std::to_string(promised) + " bytes but the header implies " +
                   std::to_string(payloadBytes));
  if (promised > kZstdMaxRatio * frameBytes)
    return corrupt("zstd frame of " + std::to_string(frameBytes) + " bytes cannot hold " +
                   std::to_string(promised));

  // Not zero-filled: zstd writes every byte of a frame that decompresses to its full size.
  std::unique_ptr<uint8_t[]> payload(new uint8_t[payloadBytes]);
  thread_local std::unique_ptr<ZSTD_DCtx, size_t (*)(ZSTD_DCtx*)> context(ZSTD_createDCtx(),
                                                                          ZSTD_freeDCtx);
  const size_t got =
      ZSTD_decompressDCtx(context.get(), payload.get(), payloadBytes, frame, frameBytes);
  if (ZSTD_isError(got) || got != payloadBytes) return corrupt("zstd data does not decompress");

  ldi.layerCounts.assign(payload.get(), payload.get() + pixelCount);
  uint64_t sum = 0;
  for (uint8_t count : ldi.layerCounts) sum += count;
  if (sum != n)
    return corrupt("layer counts sum to " + std::to_string(sum) + " but " + std::to_string(n) +
                   " depth pixels follow");

  const uint8_t* planes = payload.get() + pixelCount;
  const auto plane = [&](uint64_t k, uint64_t i) { return uint32_t(planes[k * n + i]); };
  ldi.pixels.resize(n);
  uint64_t i = 0;
  uint32_t lastFirstDepth = 0;
  for (uint64_t p = 0; p < pixelCount; ++p) {
    uint32_t previous = lastFirstDepth;
    for (uint32_t layer = 0; layer < ldi.layerCounts[p]; ++layer, ++i) {
      const uint32_t code = plane(4, i) << 16 | plane(5, i) << 8 | plane(6, i);
      if (code > kLdiMaxDepth)
        return corrupt("depth pixel " + std::to_string(i) + " has a depth beyond 20 bits");
      const uint32_t row = plane(7, i), col = plane(8, i);
      if (row >= kSplatGrid || col >= kSplatGrid)
        return corrupt("depth pixel " + std::to_string(i) + " has splat row " +
                       std::to_string(row) + ", column " + std::to_string(col) +
                       " outside the 45 x 45 grid");
      const uint32_t depth = unzigzag20(code, previous);
      const uint32_t rgba = plane(0, i) | plane(1, i) << 8 | plane(2, i) << 16 | plane(3, i) << 24;
      ldi.pixels[i] = DepthPixel::make(rgba, depth, row * kSplatGrid + col);
      previous = depth;
      if (layer == 0) lastFirstDepth = depth;
    }
  }
  return ldi;
}

}  // namespace terralod::veg
