#pragma once
// Layered depth images (Shade, Gortler, He, Szeliski 1998) as the vegetation tiles keep them:
// an orthographic camera, and for each of its pixels every surface a ray through that pixel
// met, front to back. A depth pixel is 8 bytes: sRGB colour with alpha, a 20-bit depth and an
// 11-bit splat index (the surface normal, octahedrally quantized; the renderer turns normal
// and distance into a splat footprint).

#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

#include "terralod/core/result.h"

namespace terralod::veg {

inline constexpr uint32_t kLdiDepthBits = 20;
inline constexpr uint32_t kLdiSplatBits = 11;
inline constexpr uint32_t kLdiMaxDepth = (1u << kLdiDepthBits) - 1;
inline constexpr uint32_t kLdiMaxSplat = (1u << kLdiSplatBits) - 1;
/// Largest splat index encodeSplatNormal makes (45 × 45 codes); readers refuse larger ones.
inline constexpr uint32_t kLdiMaxSplatCode = 45 * 45 - 1;

struct DepthPixel {
  uint32_t rgba = 0;    ///< r in the low byte, then g, b, a
  uint32_t zsplat = 0;  ///< depth in bits 0–19, splat index in bits 20–30, bit 31 zero

  uint32_t depth() const { return zsplat & kLdiMaxDepth; }
  uint32_t splat() const { return (zsplat >> kLdiDepthBits) & kLdiMaxSplat; }
  static DepthPixel make(uint32_t rgba, uint32_t depth, uint32_t splat) {
    return {rgba, (depth & kLdiMaxDepth) | ((splat & kLdiMaxSplat) << kLdiDepthBits)};
  }
  bool operator==(const DepthPixel&) const = default;
};

/// Where an LDI's camera is, in its tile's frame (tile square [0, size]², ground z = 0, +z up).
/// A depth pixel (column c, row r, depth d) is the point
///   origin + (c + 0.5)·pixelSize·axisU + (r + 0.5)·pixelSize·axisV
///          + (depthMin + d·(depthMax − depthMin)/kLdiMaxDepth)·direction.
struct LdiCamera {
  uint32_t width = 0, height = 0;                                            ///< pixels
  float pixelSize = 0;                                                       ///< metres
  glm::vec3 origin{0}, axisU{1, 0, 0}, axisV{0, 1, 0}, direction{0, 0, -1};  ///< unit axes
  float depthMin = 0, depthMax = 1;  ///< metres along `direction` from the image plane

  bool operator==(const LdiCamera&) const = default;
};

struct Ldi {
  LdiCamera camera;
  std::vector<uint8_t> layerCounts;  ///< width·height, row-major from row 0
  std::vector<DepthPixel> pixels;    ///< every pixel's layers in row-major order, front first

  bool operator==(const Ldi&) const = default;
};

/// Octahedral normal quantization into the 11-bit splat index (a 45×45 grid, 2025 codes).
uint32_t encodeSplatNormal(const glm::vec3& unitNormal);
glm::vec3 decodeSplatNormal(uint32_t splat);

/// The LDI blob of a .tlv file (docs/format.md, "Vegetation files"): zstd over byte planes.
std::vector<uint8_t> encodeLdi(const Ldi& ldi);
/// Checks everything (sizes, counts, depth order is not checked); one error line on bad bytes.
Result<Ldi> decodeLdi(const uint8_t* data, size_t size);

}  // namespace terralod::veg
