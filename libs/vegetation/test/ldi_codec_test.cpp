#include <gtest/gtest.h>
#include <zstd.h>

#include <cmath>
#include <cstring>
#include <numbers>
#include <random>

#include <glm/geometric.hpp>

#include "terralod/vegetation/ldi.h"

// Helpers in a named namespace: test files are compiled four to a unit (unity builds).
namespace terralod::veg::ldi_codec_test {

// A random LDI: each pixel empty with probability `empty`, else 1..maxLayers layers, with
// random colours, depths and splats (extremes included).
Ldi randomLdi(std::mt19937& rng, uint32_t width, uint32_t height, double empty, int maxLayers) {
  Ldi ldi;
  ldi.camera.width = width;
  ldi.camera.height = height;
  ldi.camera.pixelSize = 0.01f;
  ldi.camera.origin = {-1.5f, 2.25f, 3.125f};
  ldi.camera.axisU = glm::normalize(glm::vec3(1, 1, 0));
  ldi.camera.axisV = glm::normalize(glm::vec3(-0.5f, 0.5f, -0.7f));
  ldi.camera.direction = glm::normalize(glm::cross(ldi.camera.axisU, ldi.camera.axisV));
  ldi.camera.depthMin = -0.25f;
  ldi.camera.depthMax = 7.5f;
  std::uniform_real_distribution<double> unit(0, 1);
  std::uniform_int_distribution<uint32_t> any;
  for (uint64_t p = 0; p < uint64_t(width) * height; ++p) {
    const int layers = unit(rng) < empty ? 0 : 1 + int(unit(rng) * maxLayers) % maxLayers;
    ldi.layerCounts.push_back(uint8_t(layers));
    for (int k = 0; k < layers; ++k) {
      const uint32_t r = any(rng);
      const uint32_t depth = r % 7 == 0 ? kLdiMaxDepth : r % 11 == 0 ? 0 : any(rng) & kLdiMaxDepth;
      const uint32_t splat = r % 5 == 0 ? kLdiMaxSplatCode : r % 13 == 0 ? 0 : any(rng) % 2025;
      ldi.pixels.push_back(DepthPixel::make(any(rng), depth, splat));
    }
  }
  return ldi;
}

double angleDegrees(const glm::vec3& a, const glm::vec3& b) {
  return std::acos(std::clamp(double(glm::dot(a, b)), -1.0, 1.0)) * 180 / std::numbers::pi;
}

// A blob with the header of `valid` and `payload` as its zstd frame: for payloads the
// encoder would never write.
std::vector<uint8_t> withPayload(const std::vector<uint8_t>& valid,
                                 const std::vector<uint8_t>& payload) {
  std::vector<uint8_t> blob(valid.begin(), valid.begin() + 80);
  blob.resize(80 + ZSTD_compressBound(payload.size()));
  const size_t n =
      ZSTD_compress(blob.data() + 80, blob.size() - 80, payload.data(), payload.size(), 1);
  blob.resize(80 + n);
  return blob;
}

std::vector<uint8_t> payloadOf(const std::vector<uint8_t>& blob) {
  std::vector<uint8_t> payload(ZSTD_getFrameContentSize(blob.data() + 80, blob.size() - 80));
  ZSTD_decompress(payload.data(), payload.size(), blob.data() + 80, blob.size() - 80);
  return payload;
}

std::string decodeError(const std::vector<uint8_t>& blob) {
  auto r = decodeLdi(blob.data(), blob.size());
  return r.ok() ? "decoded" : r.error().message;
}

// What every decoded LDI promises a renderer, whatever bytes it came from.
void expectConsistent(const Ldi& ldi) {
  ASSERT_EQ(ldi.layerCounts.size(), uint64_t(ldi.camera.width) * ldi.camera.height);
  uint64_t sum = 0;
  for (uint8_t c : ldi.layerCounts) sum += c;
  ASSERT_EQ(sum, ldi.pixels.size());
  for (const DepthPixel& p : ldi.pixels) {
    ASSERT_EQ(p.zsplat >> 31, 0u);
    ASSERT_LE(p.splat(), kLdiMaxSplatCode);
  }
  ASSERT_TRUE(std::isfinite(ldi.camera.pixelSize) && ldi.camera.pixelSize > 0);
  ASSERT_GT(ldi.camera.depthMax, ldi.camera.depthMin);
}

TEST(LdiSplatNormal, RoundTripsWithinFourDegrees) {
  // A 45 × 45 octahedral grid: cells are about 4.5° across where the map stretches most, so
  // the worst case is about 3.6° (measured 3.58° over 2 million normals), the mean 1.8°.
  std::mt19937 rng(3);
  std::normal_distribution<float> gauss;
  double worst = 0, sum = 0;
  const int n = 200000;
  for (int i = 0; i < n; ++i) {
    const glm::vec3 v = glm::normalize(glm::vec3(gauss(rng), gauss(rng), gauss(rng)));
    const uint32_t code = encodeSplatNormal(v);
    ASSERT_LE(code, kLdiMaxSplatCode);
    const double a = angleDegrees(decodeSplatNormal(code), v);
    worst = std::max(worst, a);
    sum += a;
  }
  EXPECT_LT(worst, 3.7);
  EXPECT_LT(sum / n, 2.0);
}

TEST(LdiSplatNormal, EveryCodeDecodesToAUnitNormalThatEncodesBackToIt) {
  for (uint32_t code = 0; code <= kLdiMaxSplatCode; ++code) {
    const glm::vec3 n = decodeSplatNormal(code);
    EXPECT_NEAR(glm::length(n), 1.0f, 1e-5f) << code;
    EXPECT_EQ(encodeSplatNormal(n), code);
  }
  EXPECT_EQ(decodeSplatNormal(encodeSplatNormal({0, 0, 1})), glm::vec3(0, 0, 1));  // exactly
  EXPECT_EQ(encodeSplatNormal({0, 0, 1}), 22u * 45 + 22);
  EXPECT_EQ(encodeSplatNormal({0, 0, 5}), encodeSplatNormal({0, 0, 1}));  // normalised first
  EXPECT_LE(encodeSplatNormal({0, 0, 0}), kLdiMaxSplatCode);              // no direction: any
  EXPECT_LE(encodeSplatNormal({NAN, 0, 1}), kLdiMaxSplatCode);
}

TEST(LdiCodec, RoundTripsRandomLdis) {
  std::mt19937 rng(11);
  struct Case {
    uint32_t width, height;
    double empty;
    int maxLayers;
  } cases[] = {{1, 1, 0, 1},     {1, 1, 1, 1},     {7, 3, 0.5, 4},
               {64, 48, 0.7, 4}, {33, 17, 0, 255}, {200, 1, 0.9, 3},
               {1, 300, 0, 2},   {4096, 1, 1, 1},  {5, 4096, 0.99, 8}};
  for (const Case& c : cases) {
    const Ldi ldi = randomLdi(rng, c.width, c.height, c.empty, c.maxLayers);
    const std::vector<uint8_t> blob = encodeLdi(ldi);
    auto back = decodeLdi(blob.data(), blob.size());
    ASSERT_TRUE(back.ok()) << back.error().message;
    EXPECT_TRUE(*back == ldi) << c.width << " x " << c.height;
  }
}

TEST(LdiCodec, KeepsEveryCameraBit) {
  std::mt19937 rng(5);
  Ldi ldi = randomLdi(rng, 3, 2, 0.3, 3);
  ldi.camera.pixelSize = 1e-30f;
  ldi.camera.origin = {-0.0f, 3.4e38f, 1e-40f};  // negative zero, huge, subnormal
  ldi.camera.depthMin = -1e38f;
  ldi.camera.depthMax = 1e38f;
  const std::vector<uint8_t> blob = encodeLdi(ldi);
  auto back = decodeLdi(blob.data(), blob.size());
  ASSERT_TRUE(back.ok()) << back.error().message;
  EXPECT_EQ(std::signbit(back->camera.origin.x), true);
  EXPECT_EQ(std::memcmp(&back->camera, &ldi.camera, sizeof ldi.camera), 0);
}

TEST(LdiCodec, RefusesBadHeadersWithOneLine) {
  std::mt19937 rng(2);
  const std::vector<uint8_t> blob = encodeLdi(randomLdi(rng, 4, 3, 0.2, 3));
  const auto withU32 = [&](size_t at, uint32_t v) {
    auto b = blob;
    std::memcpy(b.data() + at, &v, 4);
    return decodeError(b);
  };
  const auto withF32 = [&](size_t at, float v) {
    auto b = blob;
    std::memcpy(b.data() + at, &v, 4);
    return decodeError(b);
  };
  EXPECT_EQ(withU32(0, 0x12345678), "corrupt LDI: bad magic");
  EXPECT_EQ(withU32(4, 2), "corrupt LDI: version 2 is not supported (this reads 1)");
  EXPECT_EQ(withU32(8, 0), "corrupt LDI: size 0 x 3 is outside 1..4096 pixels");
  EXPECT_EQ(withU32(12, 4097), "corrupt LDI: size 4 x 4097 is outside 1..4096 pixels");
  EXPECT_EQ(withF32(20, 0), "corrupt LDI: pixel size is not positive");
  EXPECT_EQ(withF32(20, NAN), "corrupt LDI: pixel size is not positive");
  EXPECT_EQ(withF32(24, INFINITY), "corrupt LDI: camera position or axes are not finite");
  EXPECT_EQ(withF32(68, NAN), "corrupt LDI: camera position or axes are not finite");
  EXPECT_EQ(withF32(72, 7.5f), "corrupt LDI: depth range is empty or not finite");
  EXPECT_EQ(withF32(76, INFINITY), "corrupt LDI: depth range is empty or not finite");
  // A header promising more or fewer depth pixels than the frame holds.
  const std::string more = withU32(16, 100);
  EXPECT_NE(more.find("corrupt LDI: payload is"), std::string::npos) << more;
  EXPECT_EQ(withU32(16, 0xFFFFFFFF),
            "corrupt LDI: 4294967295 depth pixels are more than an LDI may hold");
  EXPECT_EQ(withU32(16, 12 * 255 + 1),
            "corrupt LDI: 3061 depth pixels cannot fit in 12 pixels of at most 255 layers");
  auto trailing = blob;
  trailing.push_back(0);
  EXPECT_EQ(decodeError(trailing), "corrupt LDI: 1 bytes follow the zstd frame");
  auto notZstd = blob;
  notZstd[80] ^= 0xFF;
  EXPECT_EQ(decodeError(notZstd), "corrupt LDI: payload is not a zstd frame");
}

TEST(LdiCodec, RefusesPayloadsThatDoNotAddUp) {
  std::mt19937 rng(4);
  const Ldi ldi = randomLdi(rng, 4, 3, 0, 1);  // 12 pixels of one layer each
  const std::vector<uint8_t> blob = encodeLdi(ldi);
  std::vector<uint8_t> payload = payloadOf(blob);
  ASSERT_EQ(payload.size(), 12u + 9 * 12);
  {
    auto p = payload;
    p[5] = 0;  // one pixel fewer layers: counts sum to 11 with 12 depth pixels
    EXPECT_EQ(decodeError(withPayload(blob, p)),
              "corrupt LDI: layer counts sum to 11 but 12 depth pixels follow");
  }
  {
    auto p = payload;
    p[12 + 4 * 12 + 3] = 0x10;  // depth code plane, high byte: 21 bits
    EXPECT_EQ(decodeError(withPayload(blob, p)),
              "corrupt LDI: depth pixel 3 has a depth beyond 20 bits");
  }
  {
    auto p = payload;
    p[12 + 7 * 12 + 2] = 45;  // splat row
    EXPECT_NE(decodeError(withPayload(blob, p)).find("depth pixel 2 has splat row 45"),
              std::string::npos);
    p[12 + 7 * 12 + 2] = 44;
    p[12 + 8 * 12 + 2] = 45;  // splat column
    EXPECT_NE(decodeError(withPayload(blob, p)).find("outside the 45 x 45 grid"),
              std::string::npos);
  }
  {
    auto p = payload;
    p.pop_back();  // a frame of the wrong size
    EXPECT_EQ(decodeError(withPayload(blob, p)),
              "corrupt LDI: payload is 119 bytes but the header implies 120");
  }
}

TEST(LdiCodec, RoundTripsTheLargestEmptyLdi) {
  Ldi empty;  // 16 MiB of zero layer counts, which zstd keeps in a few hundred bytes
  empty.camera.width = empty.camera.height = 4096;
  empty.camera.pixelSize = 1;
  empty.layerCounts.assign(size_t(4096) * 4096, 0);
  const std::vector<uint8_t> blob = encodeLdi(empty);
  auto back = decodeLdi(blob.data(), blob.size());
  ASSERT_TRUE(back.ok()) << back.error().message;
  EXPECT_TRUE(*back == empty);
}

TEST(LdiCodec, RefusesAFrameThatPromisesMoreThanItCanHoldBeforeAllocating) {
  std::mt19937 rng(6);
  std::vector<uint8_t> blob = encodeLdi(randomLdi(rng, 1, 1, 1, 1));
  const uint32_t side = 4096;  // promises 16 MiB of layer counts...
  std::memcpy(blob.data() + 8, &side, 4);
  std::memcpy(blob.data() + 12, &side, 4);
  blob.resize(80);
  // ...in a hand-made frame of 17 bytes: magic, a single-segment descriptor with an 8-byte
  // content size of 16 MiB, then one last RLE block of 128 KiB of zeros.
  const uint8_t frame[] = {0x28, 0xB5, 0x2F, 0xFD, 0xE0, 0,    0,    0,   1,
                           0,    0,    0,    0,    0x03, 0x00, 0x10, 0x00};
  blob.insert(blob.end(), frame, frame + sizeof frame);
  EXPECT_EQ(decodeError(blob), "corrupt LDI: zstd frame of 17 bytes cannot hold 16777216");
}

TEST(LdiCodec, EveryTruncationIsRefused) {
  std::mt19937 rng(8);
  const std::vector<uint8_t> blob = encodeLdi(randomLdi(rng, 9, 7, 0.4, 5));
  for (size_t n = 0; n < blob.size(); ++n) {
    auto r = decodeLdi(blob.data(), n);
    ASSERT_FALSE(r.ok()) << n;
    EXPECT_EQ(r.error().message.find('\n'), std::string::npos);
    EXPECT_EQ(r.error().message.rfind("corrupt LDI: ", 0), 0u) << r.error().message;
  }
}

TEST(LdiCodec, EveryFlippedBitIsRefusedOrDecodesToAConsistentLdi) {
  // The blob has no checksum of its own (the file's directory has one), so a flip may decode,
  // e.g. in a camera float or a colour: never to anything a renderer could trip over.
  std::mt19937 rng(9);
  const std::vector<uint8_t> blob = encodeLdi(randomLdi(rng, 6, 5, 0.3, 4));
  int refused = 0;
  for (size_t i = 0; i < blob.size(); ++i)
    for (int bit = 0; bit < 8; ++bit) {
      auto b = blob;
      b[i] ^= uint8_t(1 << bit);
      auto r = decodeLdi(b.data(), b.size());
      if (!r.ok()) {
        ++refused;
        EXPECT_EQ(r.error().message.find('\n'), std::string::npos);
        continue;
      }
      expectConsistent(*r);
    }
  EXPECT_GT(refused, 0);
}

}  // namespace terralod::veg::ldi_codec_test
