#include "terralod/build/texture_plan.h"

#include <algorithm>
#include <bit>
#include <cmath>

#include "terralod/format/texture_codec.h"

namespace terralod {
namespace {

constexpr uint32_t kMinIntervals = 4;  // at least 5 texels per side

// Texel intervals per side: the eq. 7 count rounded up to a power of two, then capped.
uint32_t intervals(double wanted, uint64_t cap, uint8_t& flags) {
  const uint64_t want = std::bit_ceil(uint64_t(std::max(1.0, std::ceil(wanted - 1e-9))));
  const uint64_t hardCap = kMaxTextureSize - 1;
  uint64_t n = std::max<uint64_t>(want, kMinIntervals);
  flags = 0;
  if (n > cap || n > hardCap) {
    flags = kTextureSourceLimited;
    n = std::min(cap, hardCap);
  }
  return uint32_t(std::max<uint64_t>(n, std::min<uint64_t>(kMinIntervals, cap)));
}

}  // namespace

std::vector<TextureLevel> planTextures(const TreeLayout& layout,
                                       const std::vector<double>& levelError, double spacingX,
                                       double spacingY, double textureTau, uint32_t colorRefine) {
  std::vector<TextureLevel> plan(size_t(layout.levelCount()));
  const double spacing = std::max(spacingX, spacingY);
  for (int32_t level = 0; level < layout.levelCount(); ++level) {
    const uint64_t cells = uint64_t(layout.chunkCells(level));
    const double texelMetres = levelError[size_t(level)] / textureTau;  // eq. 7
    const double wanted = double(cells) * spacing / texelMetres;
    TextureLevel& t = plan[size_t(level)];
    t.normalSize = intervals(wanted, cells, t.normalFlags) + 1;
    t.colorSize = intervals(wanted, cells * colorRefine, t.colorFlags) + 1;
    if (level > 0) {
      const TextureLevel& parent = plan[size_t(level - 1)];
      t.inherited =
          parent.colorSize == 2 * t.colorSize - 1 && parent.normalSize == 2 * t.normalSize - 1;
    }
  }
  return plan;
}

void halveColourTiles(std::vector<TextureLevel>& plan) {
  for (TextureLevel& t : plan) {
    t.colorSize = std::max(2u, (t.normalSize - 1) / 2 + 1);
    t.colorFlags = t.normalFlags;
  }
  for (size_t level = 1; level < plan.size(); ++level)
    plan[level].inherited =
        plan[level].inherited && plan[level - 1].colorSize == 2 * plan[level].colorSize - 1;
}

}  // namespace terralod
