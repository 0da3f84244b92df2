#include "terralod/vegetation/wang_tiling.h"

#include <cassert>

#include "random_stream.h"

namespace terralod::veg {
namespace {

// The random number of tile (x, y): the same wherever and however it is asked for.
uint32_t tileHash(uint64_t seed, uint32_t x, uint32_t y) {
  return uint32_t(mix64(mix64(seed ^ 0x9e3779b97f4a7c15ull) + (uint64_t(y) << 32 | x)) >> 32);
}

constexpr int indexOf(int west, int south, int north) {
  return west << 2 | south << 1 | north;
}

}  // namespace

TileEdges prototileEdges(int k) {
  assert(k >= 0 && k < kWangPrototiles);
  const uint8_t west = (k >> 2) & 1, south = (k >> 1) & 1, north = k & 1;
  return {north, uint8_t(south ^ north), south, west};
}

const std::array<TileEdges, kWangPrototiles>& prototileSet() {
  static const std::array<TileEdges, kWangPrototiles> set = [] {
    std::array<TileEdges, kWangPrototiles> s;
    for (int k = 0; k < kWangPrototiles; ++k) s[k] = prototileEdges(k);
    return s;
  }();
  return set;
}

// The scanline's choice among the compatible prototiles in index order (west, south, north
// bits, most significant first) is hash % count: 8 for the first tile, 4 along the south row
// (south and north free) and the west column (west and north free), 2 elsewhere (north
// free). So the north colour is always bit 0 of the hash, and a free south or west colour the
// next bit(s) up.
int WangTiling::at(uint32_t x, uint32_t y) const {
  assert(x < mWidth && y < mHeight);
  const uint32_t h = tileHash(mSeed, x, y);
  const int west = x == 0 ? (h >> (y == 0 ? 2 : 1)) & 1 : eastOf(x - 1, y);
  return indexOf(west, southOf(x, y), northOf(x, y));
}

int WangTiling::northOf(uint32_t x, uint32_t y) const {
  return tileHash(mSeed, x, y) & 1;
}

int WangTiling::southOf(uint32_t x, uint32_t y) const {
  return y == 0 ? (tileHash(mSeed, x, 0) >> 1) & 1 : northOf(x, y - 1);
}

int WangTiling::eastOf(uint32_t x, uint32_t y) const {
  return southOf(x, y) ^ northOf(x, y);
}

LaidTiling scanlineTiling(uint32_t width, uint32_t height, uint64_t seed) {
  LaidTiling t{width, height, std::vector<uint8_t>(size_t(width) * height)};
  const auto& set = prototileSet();
  for (uint32_t y = 0; y < height; ++y) {
    for (uint32_t x = 0; x < width; ++x) {
      int candidates[kWangPrototiles], count = 0;
      for (int k = 0; k < kWangPrototiles; ++k) {
        if (x > 0 && set[k].west != set[t.at(x - 1, y)].east) continue;
        if (y > 0 && set[k].south != set[t.at(x, y - 1)].north) continue;
        candidates[count++] = k;
      }
      assert(count > 0);
      t.prototiles[size_t(y) * width + x] = uint8_t(candidates[tileHash(seed, x, y) % count]);
    }
  }
  return t;
}

bool tilingIsValid(const LaidTiling& t) {
  const auto& set = prototileSet();
  for (uint32_t y = 0; y < t.height; ++y)
    for (uint32_t x = 0; x < t.width; ++x) {
      const TileEdges& e = set[t.at(x, y)];
      if (x + 1 < t.width && e.east != set[t.at(x + 1, y)].west) return false;
      if (y + 1 < t.height && e.north != set[t.at(x, y + 1)].south) return false;
    }
  return true;
}

std::array<int, 9> contextAround(int prototile, uint64_t seed) {
  for (uint64_t s = seed * 1000003ull;; ++s) {
    const WangTiling t(3, 3, s);
    if (t.at(1, 1) != prototile) continue;
    std::array<int, 9> c;
    for (int k = 0; k < 9; ++k) c[k] = t.at(uint32_t(k % 3), uint32_t(k / 3));
    return c;
  }
}

}  // namespace terralod::veg
