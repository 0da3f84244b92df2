#include "terralod/vegetation/directional_textures.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <vector>

#include <glm/common.hpp>
#include <glm/vec2.hpp>

#include "terralod/core/parallel.h"
#include "terralod/vegetation/ldi_camera.h"
#include "terralod/vegetation/ldi_warp.h"
#include "terralod/vegetation/wang_tiling.h"

namespace terralod::veg {
namespace {

// The ring whose LDIs were sampled nearest `elevation` (degrees).
int ringFor(const BakeSettings& s, float elevation) {
  int best = 0;
  for (int r = 1; r < kLdiResolutions; ++r)
    if (std::abs(s.elevations[size_t(r)] * 180.0f / std::numbers::pi_v<float> - elevation) <
        std::abs(s.elevations[size_t(best)] * 180.0f / std::numbers::pi_v<float> - elevation))
      best = r;
  return best;
}

// A tiling (2·reach + 1) tiles a side with `prototile` in the middle, row by row from the
// south-west (deterministic for a seed).
std::vector<int> windowAround(int prototile, int reach, uint64_t seed) {
  const uint32_t side = uint32_t(2 * reach + 1);
  for (uint64_t s = seed * 7919ull + uint64_t(reach);; ++s) {
    const WangTiling t(side, side, s);
    if (t.at(uint32_t(reach), uint32_t(reach)) != prototile) continue;
    std::vector<int> w(size_t(side) * side);
    for (uint32_t y = 0; y < side; ++y)
      for (uint32_t x = 0; x < side; ++x) w[size_t(y) * side + x] = t.at(x, y);
    return w;
  }
}

}  // namespace

Result<DirectionalTextures> makeDirectionalTextures(const VegetationReader& file, int size) {
  const BakeSettings& s = file.header().settings;
  const float tile = s.tileSize;
  // The LDIs the textures need, read once.
  std::map<int, WarpLdi> ldis;
  for (int e = 0; e < kTextureElevationCount; ++e) {
    const int ring = ringFor(s, kTextureElevations[size_t(e)]);
    for (int k = 0; k < kPrototiles; ++k)
      for (int d = 0; d < kLdiDirections; ++d) {
        const int index = ldiIndex(k, ring, d);
        if (ldis.count(index)) continue;
        auto ldi = file.readLdi(k, ring, d);
        if (!ldi) return ldi.error();
        ldis.emplace(index, WarpLdi::of(std::move(ldi).value()));
      }
  }
  DirectionalTextures out;
  out.size = size;
  out.rgba.assign(size_t(DirectionalTextures::kCount) * size_t(size) * size_t(size), 0);
  parallelFor(size_t(DirectionalTextures::kCount), hardwareThreads(), [&](size_t i, unsigned) {
    const int e = int(i) % kTextureElevationCount;
    const int d = int(i) / kTextureElevationCount % kLdiDirections;
    const int k = int(i) / kTextureElevationCount / kLdiDirections;
    const int ring = ringFor(s, kTextureElevations[size_t(e)]);
    // The line of sight: azimuth of direction d, down at the texture's elevation.
    const float azimuth = directionAzimuth(d);
    const float elevation = kTextureElevations[size_t(e)] * std::numbers::pi_v<float> / 180.0f;
    const glm::vec3 v(std::sin(azimuth) * std::cos(elevation),
                      std::cos(azimuth) * std::cos(elevation), -std::sin(elevation));
    // Tile frame → clip: along v onto the ground (x, y) of the centre tile [0, tile]², depth
    // along v. Column-major: m[column][row].
    const glm::vec2 slide = glm::vec2(v.x, v.y) / std::sin(elevation);
    const float depthScale = 1.0f / (20.0f * tile);
    glm::mat4 toClip(0.0f);
    toClip[0] = {2.0f / tile, 0.0f, v.x * depthScale, 0.0f};
    toClip[1] = {0.0f, 2.0f / tile, v.y * depthScale, 0.0f};
    toClip[2] = {2.0f * slide.x / tile, 2.0f * slide.y / tile, v.z * depthScale, 0.0f};
    toClip[3] = {-1.0f, -1.0f, 0.0f, 1.0f};
    WarpTarget target(size, size);
    // Whatever stands between a far viewer and the ground point: at low elevations plants
    // many tiles nearer the viewer (a plant h high lands h / tan(elevation) beyond its foot).
    const int reach = int(std::ceil(s.tileHeight / (std::tan(elevation) * tile))) + 1;
    const std::vector<int> window = windowAround(k, reach, s.seed);
    const int side = 2 * reach + 1;
    std::vector<glm::ivec2> offsets;
    for (int y = -reach; y <= reach; ++y)
      for (int x = -reach; x <= reach; ++x) {
        // The tile's box [o, o + tile]² × [0, tileHeight] projected onto the ground along v:
        // its footprint, slid by up to slide · tileHeight, must meet the centre tile.
        const glm::vec2 lo(tile * float(x), tile * float(y)), hi = lo + tile;
        const glm::vec2 a = glm::min(lo, lo + slide * s.tileHeight);
        const glm::vec2 b = glm::max(hi, hi + slide * s.tileHeight);
        if (b.x <= 0 || b.y <= 0 || a.x >= tile || a.y >= tile) continue;
        offsets.push_back({x, y});
      }
    // Farther from the viewer first; the order and the depth test do the rest.
    const glm::vec2 along(v.x, v.y);
    std::sort(offsets.begin(), offsets.end(), [&](glm::ivec2 a, glm::ivec2 b) {
      return glm::dot(glm::vec2(a), along) > glm::dot(glm::vec2(b), along);
    });
    for (const glm::ivec2 o : offsets) {
      const glm::vec3 offset(tile * float(o.x), tile * float(o.y), 0.0f);
      glm::mat4 m = toClip;
      m[3] += toClip * glm::vec4(offset, 0.0f);
      // The eye far back along the line of sight, in the neighbour's frame.
      const glm::vec3 eye = glm::vec3(0.5f * tile) - 1000.0f * tile * v - offset;
      const int prototile = window[size_t((o.y + reach) * side + o.x + reach)];
      warpLdi(ldis.at(ldiIndex(prototile, ring, d)), m, eye, target);
    }
    uint32_t* texels = &out.rgba[i * size_t(size) * size_t(size)];
    for (int p = 0; p < size * size; ++p) texels[p] = packRgba8(&target.rgba[4 * size_t(p)]);
  });
  return out;
}

}  // namespace terralod::veg
