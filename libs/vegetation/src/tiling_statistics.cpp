#include "terralod/vegetation/tiling_statistics.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cassert>
#include <cmath>

#include "random_stream.h"

namespace terralod::veg {
namespace {

using StatsRgb = std::array<uint8_t, 3>;

// 16 distinguishable colours (Figure 4 gives each prototile a random colour).
constexpr std::array<StatsRgb, 16> kTilePalette = {{
    {31, 119, 180},   // blue
    {255, 127, 14},   // orange
    {44, 160, 44},    // green
    {214, 39, 40},    // red
    {148, 103, 189},  // purple
    {140, 86, 75},    // brown
    {227, 119, 194},  // pink
    {255, 221, 0},    // yellow
    {23, 190, 207},   // cyan
    {188, 189, 34},   // olive
    {0, 0, 128},      // navy
    {0, 90, 50},      // dark green
    {120, 0, 60},     // maroon
    {127, 127, 127},  // grey
    {170, 255, 195},  // mint
    {30, 30, 30},     // near black
}};

constexpr StatsRgb kFigureBackground = {208, 208, 208};

void blitPanel(RgbImage& target, const RgbImage& source, int left, int top) {
  assert(left >= 0 && top >= 0 && left + source.width <= target.width &&
         top + source.height <= target.height);
  for (int y = 0; y < source.height; ++y)
    std::copy_n(source.pixel(0, y), size_t(source.width) * 3,
                &target.rgb[(size_t(top + y) * target.width + left) * 3]);
}

}  // namespace

TileGrid toGrid(const LaidTiling& tiling) {
  return {tiling.width, tiling.height, kWangPrototiles, tiling.prototiles};
}

TileGrid toGrid(const WangTiling& tiling) {
  return sampleGrid(tiling.width(), tiling.height(), kWangPrototiles,
                    [&](uint32_t x, uint32_t y) { return tiling.at(x, y); });
}

TileGrid independentTiling(uint32_t width, uint32_t height, int prototileCount, uint64_t seed) {
  assert(prototileCount >= 1 && prototileCount <= 256);
  const uint64_t key = mix64(seed ^ 0x6a09e667f3bcc909ull);
  return sampleGrid(width, height, prototileCount, [&](uint32_t x, uint32_t y) {
    return int((mix64(key + (uint64_t(y) << 32 | x)) >> 32) % uint64_t(prototileCount));
  });
}

int hierarchicalTileType(uint64_t i, uint64_t j) {
  assert(i >= 1 && j >= 1);
  auto bit = [](uint64_t v, int k) { return k < 64 ? int((v >> k) & 1) : 0; };
  const int a = std::countr_zero(i), b = std::countr_zero(j);
  if (a == b) {
    const int east = bit(i, a + 1) == 0, north = bit(j, b + 1) == 0;
    return 4 * (a & 1) + east + 2 * north;
  }
  const bool horizontal = b > a;
  // The arm lies on the line of the level-`line` crosses in its column (vertical) or row
  // (horizontal) and points away from the nearer of them: forwards when bit `line` of the
  // coordinate along the line is set (the nearer cross is behind).
  const int line = std::max(a, b);
  const uint64_t along = horizontal ? i : j;
  const int forwards = bit(along, line);
  return 8 + 4 * horizontal + 2 * forwards + (line & 1);
}

TileGrid hierarchicalTiling(uint32_t width, uint32_t height, uint64_t seed) {
  // An offset below 2^40 keeps i, j far from overflow; seed 0 is the unshifted structure.
  const uint64_t h = seed == 0 ? 0 : mix64(seed ^ 0xbb67ae8584caa73bull);
  const uint64_t offsetX = h & ((uint64_t(1) << 40) - 1),
                 offsetY = (h >> 20) & ((uint64_t(1) << 40) - 1);
  return sampleGrid(width, height, kHierarchicalTileTypes, [&](uint32_t x, uint32_t y) {
    return hierarchicalTileType(offsetX + x + 1, offsetY + y + 1);
  });
}

NeighbourStats neighbourStats(const TileGrid& grid) {
  assert(grid.prototileCount >= 1 && grid.prototileCount <= 256);
  assert(grid.prototiles.size() == size_t(grid.width) * grid.height);
  NeighbourStats s;
  s.sameEitherExpected = 1.0 / grid.prototileCount;
  const uint32_t w = grid.width, h = grid.height;
  if (w == 0 || h == 0) return s;

  uint64_t sameEast = 0, sameNorth = 0, withSame = 0;
  double withSameExpected = 0;
  const double differ = 1.0 - s.sameEitherExpected;
  for (uint32_t y = 0; y < h; ++y)
    for (uint32_t x = 0; x < w; ++x) {
      const int k = grid.at(x, y);
      const bool east = x + 1 < w && grid.at(x + 1, y) == k;
      const bool north = y + 1 < h && grid.at(x, y + 1) == k;
      const bool west = x > 0 && grid.at(x - 1, y) == k;
      const bool south = y > 0 && grid.at(x, y - 1) == k;
      sameEast += east;
      sameNorth += north;
      withSame += east || north || west || south;
      const int neighbours = (x + 1 < w) + (y + 1 < h) + (x > 0) + (y > 0);
      withSameExpected += 1.0 - std::pow(differ, neighbours);
    }
  const double tiles = double(w) * h;
  if (w > 1) s.sameEast = double(sameEast) / (double(w - 1) * h);
  if (h > 1) s.sameNorth = double(sameNorth) / (double(h - 1) * w);
  s.withSameNeighbour = double(withSame) / tiles;
  s.withSameNeighbourExpected = withSameExpected / tiles;

  // Clumps: 4-connected regions of one prototile, by flood fill.
  std::vector<uint8_t> seen(grid.prototiles.size(), 0);
  std::vector<uint32_t> stack;
  double sumOfSquares = 0;
  for (size_t start = 0; start < seen.size(); ++start) {
    if (seen[start]) continue;
    const uint8_t k = grid.prototiles[start];
    uint64_t size = 0;
    seen[start] = 1;
    stack.assign(1, uint32_t(start));
    while (!stack.empty()) {
      const uint32_t t = stack.back();
      stack.pop_back();
      ++size;
      const uint32_t x = t % w, y = t / w;
      auto visit = [&](uint32_t n) {
        if (!seen[n] && grid.prototiles[n] == k) {
          seen[n] = 1;
          stack.push_back(n);
        }
      };
      if (x > 0) visit(t - 1);
      if (x + 1 < w) visit(t + 1);
      if (y > 0) visit(t - w);
      if (y + 1 < h) visit(t + w);
    }
    s.largestClump = std::max(s.largestClump, size);
    sumOfSquares += double(size) * double(size);
  }
  s.meanClump = sumOfSquares / tiles;
  return s;
}

double Autocorrelation::maxAbsFromLag(int lag) const {
  double m = 0;
  for (int dy = -maxLag; dy <= maxLag; ++dy)
    for (int dx = -maxLag; dx <= maxLag; ++dx)
      if (std::max(std::abs(dx), std::abs(dy)) >= lag) m = std::max(m, std::abs(at(dx, dy)));
  return m;
}

Autocorrelation autocorrelation(const TileGrid& grid, int maxLag) {
  assert(grid.prototileCount >= 1 && grid.prototileCount <= 256);
  assert(maxLag >= 0 && uint32_t(maxLag) < grid.width && uint32_t(maxLag) < grid.height);
  Autocorrelation r;
  r.maxLag = maxLag;
  const int side = 2 * maxLag + 1;
  r.values.assign(size_t(side) * side, 0.0);
  const double chance = 1.0 / grid.prototileCount;
  const int w = int(grid.width), h = int(grid.height);
  const uint8_t* p = grid.prototiles.data();
  // Half the lags (dy > 0, or dy = 0 and dx ≥ 0); the pairs at (−dx, −dy) are the same pairs.
  for (int dy = 0; dy <= maxLag; ++dy)
    for (int dx = dy == 0 ? 0 : -maxLag; dx <= maxLag; ++dx) {
      const int x0 = std::max(0, -dx), x1 = std::min(w, w - dx);
      uint64_t same = 0;
      for (int y = 0; y + dy < h; ++y) {
        const uint8_t* a = p + size_t(y) * w;
        const uint8_t* b = p + size_t(y + dy) * w + dx;
        uint32_t rowSame = 0;
        for (int x = x0; x < x1; ++x) rowSame += a[x] == b[x];
        same += rowSame;
      }
      const double pairs = double(h - dy) * double(x1 - x0);
      // With one prototile every pair is the same: value 1 (the limit of the formula).
      const double value =
          grid.prototileCount == 1 ? 1.0 : (double(same) / pairs - chance) / (1.0 - chance);
      r.values[size_t(dy + maxLag) * side + dx + maxLag] = value;
      r.values[size_t(-dy + maxLag) * side - dx + maxLag] = value;
    }

  double onAxes = 0, offAxes = 0;
  for (int dy = -maxLag; dy <= maxLag; ++dy)
    for (int dx = -maxLag; dx <= maxLag; ++dx) {
      if (dx == 0 && dy == 0) continue;
      const double v = std::abs(r.at(dx, dy));
      r.maxAbsOffOrigin = std::max(r.maxAbsOffOrigin, v);
      (dx == 0 || dy == 0 ? onAxes : offAxes) += v;
    }
  if (maxLag > 0) {
    r.meanAbsOnAxes = onAxes / (4.0 * maxLag);
    r.meanAbsOffAxes = offAxes / (4.0 * maxLag * maxLag);
  }
  return r;
}

RgbImage renderTiling(const TileGrid& grid, int pixelsPerTile) {
  assert(grid.prototileCount <= int(kTilePalette.size()) && pixelsPerTile >= 1);
  RgbImage image{int(grid.width) * pixelsPerTile, int(grid.height) * pixelsPerTile, {}};
  image.rgb.resize(size_t(image.width) * image.height * 3);
  for (int py = 0; py < image.height; ++py) {
    const uint32_t y = grid.height - 1 - uint32_t(py / pixelsPerTile);  // north up
    uint8_t* row = &image.rgb[size_t(py) * image.width * 3];
    for (int px = 0; px < image.width; ++px) {
      const StatsRgb& c = kTilePalette[grid.at(uint32_t(px / pixelsPerTile), y)];
      std::copy(c.begin(), c.end(), row + size_t(px) * 3);
    }
  }
  return image;
}

RgbImage renderAutocorrelation(const Autocorrelation& ac, int pixelsPerLag, double scale) {
  assert(pixelsPerLag >= 1 && scale > 0);
  const int side = 2 * ac.maxLag + 1;
  RgbImage image{side * pixelsPerLag, side * pixelsPerLag, {}};
  image.rgb.resize(size_t(image.width) * image.height * 3);
  for (int py = 0; py < image.height; ++py) {
    const int dy = ac.maxLag - py / pixelsPerLag;  // dy > 0 up
    for (int px = 0; px < image.width; ++px) {
      const int dx = px / pixelsPerLag - ac.maxLag;
      const double t = std::clamp(ac.at(dx, dy) / scale, -1.0, 1.0);
      // White at 0, towards red (178, 24, 43) for +1 and blue (33, 102, 172) for −1.
      const StatsRgb end = t >= 0 ? StatsRgb{178, 24, 43} : StatsRgb{33, 102, 172};
      const double f = std::abs(t);
      uint8_t* out = &image.rgb[(size_t(py) * image.width + px) * 3];
      for (int c = 0; c < 3; ++c) out[c] = uint8_t(std::lround(255.0 + (end[c] - 255.0) * f));
    }
  }
  return image;
}

TilingFigure tilingFigure(const TilingFigureOptions& o) {
  TilingFigure figure;
  const TileGrid oursSmall = toGrid(WangTiling(o.smallTiles, o.smallTiles, o.seed));
  const TileGrid oursLarge = toGrid(WangTiling(o.largeTiles, o.largeTiles, o.seed));
  const TileGrid otherSmall = hierarchicalTiling(o.smallTiles, o.smallTiles, o.seed);
  const TileGrid otherLarge = hierarchicalTiling(o.largeTiles, o.largeTiles, o.seed);
  figure.ours = autocorrelation(oursLarge, o.maxLag);
  figure.comparison = autocorrelation(otherLarge, o.maxLag);
  figure.heatScale =
      o.heatScale > 0
          ? o.heatScale
          : std::max({figure.ours.maxAbsOffOrigin, figure.comparison.maxAbsOffOrigin, 1e-6});

  const RgbImage panels[4] = {renderTiling(oursSmall, o.smallPixelsPerTile),
                              renderTiling(oursLarge, o.largePixelsPerTile),
                              renderTiling(otherSmall, o.smallPixelsPerTile),
                              renderTiling(otherLarge, o.largePixelsPerTile)};
  const RgbImage maps[2] = {
      renderAutocorrelation(figure.ours, o.pixelsPerLag, figure.heatScale),
      renderAutocorrelation(figure.comparison, o.pixelsPerLag, figure.heatScale)};
  int topHeight = 0, width = o.gap;
  for (const RgbImage& p : panels) {
    topHeight = std::max(topHeight, p.height);
    width += p.width + o.gap;
  }
  const int pairWidth[2] = {panels[0].width + o.gap + panels[1].width,
                            panels[2].width + o.gap + panels[3].width};
  width = std::max({width, o.gap + std::max(pairWidth[0], maps[0].width) + o.gap +
                               std::max(pairWidth[1], maps[1].width) + o.gap});
  const int mapHeight = std::max(maps[0].height, maps[1].height);
  RgbImage& image = figure.image;
  image.width = width;
  image.height = o.gap + topHeight + o.gap + mapHeight + o.gap;
  image.rgb.resize(size_t(image.width) * image.height * 3);
  for (size_t i = 0; i < image.rgb.size(); i += 3)
    std::copy(kFigureBackground.begin(), kFigureBackground.end(), &image.rgb[i]);

  int left = o.gap;
  for (int pair = 0; pair < 2; ++pair) {
    const int span = std::max(pairWidth[pair], maps[pair].width);
    int x = left + (span - pairWidth[pair]) / 2;
    for (int k = 0; k < 2; ++k) {
      const RgbImage& p = panels[2 * pair + k];
      blitPanel(image, p, x, o.gap + (topHeight - p.height) / 2);
      x += p.width + o.gap;
    }
    blitPanel(image, maps[pair], left + (span - maps[pair].width) / 2, o.gap + topHeight + o.gap);
    left += span + o.gap;
  }
  return figure;
}

}  // namespace terralod::veg
