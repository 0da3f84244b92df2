// The texture quadtree's building blocks: edge-aligned resampling and mosaics of texel tiles,
// the per-level texture sizes (Ulrich eq. 7), normals from heights, and BC1/BC5 encoding.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <functional>
#include <random>

#include "alpha_block.h"
#include "bc_decode.h"
#include "temp_dir.h"
#include "terralod/build/height_source.h"
#include "terralod/build/mosaic_builder.h"
#include "terralod/build/surface_texels.h"
#include "terralod/build/texel_tile.h"
#include "terralod/build/texture_encoder.h"
#include "terralod/build/texture_plan.h"
#include "terralod/build/tree_layout.h"
#include "terralod/raster/dem_reader.h"
#include "terralod/raster/image_drape.h"
#include "test_terrain.h"
#include "texel_bytes.h"

#define STB_DXT_STATIC
#define STB_DXT_IMPLEMENTATION
#include <stb_dxt.h>

namespace terralod {
namespace {

TexelTile randomTile(uint32_t size, uint32_t channels, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
  TexelTile t(size, channels);
  for (float& v : t.values) v = unit(rng);
  return t;
}

bool bitwiseEqual(float a, float b) {
  return std::memcmp(&a, &b, sizeof a) == 0;
}

// ---------------------------------------------------------------------------------------------
// resampleTile

const uint32_t kSizes[] = {2, 3, 5, 7, 9, 16, 17, 32, 33, 64, 65, 100, 129};

TEST(ResampleTile, ConstantStaysConstant) {
  const float c[3] = {0.25f, -0.5f, 7.0f};
  for (uint32_t from : {2u, 5u, 17u, 33u, 65u}) {
    TexelTile t(from, 3);
    for (uint32_t i = 0; i < from * from; ++i) std::memcpy(&t.values[i * 3], c, sizeof c);
    for (uint32_t to : kSizes) {
      const TexelTile r = resampleTile(t, to);
      ASSERT_EQ(r.size, to);
      ASSERT_EQ(r.channels, 3u);
      ASSERT_EQ(r.values.size(), size_t(to) * to * 3);
      for (uint32_t y = 0; y < to; ++y)
        for (uint32_t x = 0; x < to; ++x)
          for (int ch = 0; ch < 3; ++ch)
            ASSERT_NEAR(r.at(x, y)[ch], c[ch], 1e-6 * std::abs(c[ch]))
                << from << " -> " << to << " at " << x << "," << y;
    }
  }
}

// f(u, v) = a + b u + c v over the tile's edge-aligned coordinates u = x / (size - 1).
TexelTile rampTile(uint32_t size, double a, double b, double c) {
  TexelTile t(size, 1);
  for (uint32_t y = 0; y < size; ++y)
    for (uint32_t x = 0; x < size; ++x)
      t.at(x, y)[0] = float(a + b * x / double(size - 1) + c * y / double(size - 1));
  return t;
}

// Worst deviation of a resampled ramp from the ramp itself.
double rampError(uint32_t from, uint32_t to) {
  const double a = 0.3, b = 1.7, c = -0.9;
  const TexelTile r = resampleTile(rampTile(from, a, b, c), to);
  double worst = 0;
  for (uint32_t y = 0; y < to; ++y)
    for (uint32_t x = 0; x < to; ++x)
      worst = std::max(
          worst, std::abs(r.at(x, y)[0] - (a + b * x / double(to - 1) + c * y / double(to - 1))));
  return worst;
}

// The sizes the texture quadtree resamples between: 2^k + 1 tiles (levels, mosaics of
// 2n - 1 texels) up and down.
TEST(ResampleTile, LinearRampStaysLinearBetweenPowerOfTwoPlusOneSizes) {
  for (uint32_t from : {3u, 5u, 9u, 17u, 33u, 65u, 129u})
    for (uint32_t to : {2u, 3u, 5u, 9u, 17u, 33u, 65u, 129u})
      EXPECT_LT(rampError(from, to), 1e-4) << from << " -> " << to;
}

// The mip chain's sizes (size >> m: 65, 32, 16, ...; encodeColorLayer/encodeNormalLayer
// resample each level from the one before) and other ratios that are not whole numbers.
// With a step that is not a whole number a tent's taps sampled at whole texels have their
// centroid off the output texel (a ramp moved by up to 0.045 source texels before the taps
// were tilted to put it back).
TEST(ResampleTile, LinearRampStaysLinearForMipSizesAndOtherRatios) {
  using Step = std::pair<uint32_t, uint32_t>;
  const std::vector<Step> mips = {{65, 32}, {32, 16}, {16, 8}, {8, 4}, {4, 2}, {33, 16}, {129, 64}};
  const std::vector<Step> down = {{17, 7}, {17, 12}, {100, 9}};
  const std::vector<Step> up = {{9, 100}, {5, 16}, {17, 40}};
  for (const std::vector<Step>& steps : {mips, down, up})
    for (auto [from, to] : steps) EXPECT_LT(rampError(from, to), 1e-4) << from << " -> " << to;
}

TEST(ResampleTile, CornersAndBordersComeFromTheSourceBorders) {
  const TexelTile t = randomTile(17, 2, 11);
  for (uint32_t to : kSizes) {
    const TexelTile r = resampleTile(t, to);
    const uint32_t e = to - 1, s = t.size - 1;
    for (int ch = 0; ch < 2; ++ch) {
      EXPECT_TRUE(bitwiseEqual(r.at(0, 0)[ch], t.at(0, 0)[ch])) << to;
      EXPECT_TRUE(bitwiseEqual(r.at(e, 0)[ch], t.at(s, 0)[ch])) << to;
      EXPECT_TRUE(bitwiseEqual(r.at(0, e)[ch], t.at(0, s)[ch])) << to;
      EXPECT_TRUE(bitwiseEqual(r.at(e, e)[ch], t.at(s, s)[ch])) << to;
    }
  }
  // A border is the 1-D resampling of the source border: change the interior and the
  // borders stay as they were.
  TexelTile other = t;
  for (uint32_t y = 1; y + 1 < t.size; ++y)
    for (uint32_t x = 1; x + 1 < t.size; ++x) other.at(x, y)[0] += 5.0f;
  for (uint32_t to : kSizes) {
    const TexelTile r = resampleTile(t, to), q = resampleTile(other, to);
    for (uint32_t k = 0; k < to; ++k)
      for (uint32_t b : {0u, to - 1}) {
        ASSERT_TRUE(bitwiseEqual(r.at(k, b)[0], q.at(k, b)[0])) << to << " row " << b;
        ASSERT_TRUE(bitwiseEqual(r.at(b, k)[0], q.at(b, k)[0])) << to << " column " << b;
      }
    if (to >= 3) {  // ... and the interior does change
      bool changed = false;
      for (uint32_t y = 1; y + 1 < to; ++y)
        for (uint32_t x = 1; x + 1 < to; ++x) changed |= r.at(x, y)[0] != q.at(x, y)[0];
      EXPECT_TRUE(changed) << to;
    }
  }
}

TEST(ResampleTile, SameSizeIsACopy) {
  const TexelTile t = randomTile(9, 3, 4);
  const TexelTile r = resampleTile(t, 9);
  EXPECT_EQ(r.size, 9u);
  EXPECT_EQ(r.values, t.values);
}

// Two neighbours whose shared border texels agree still agree after any resampling: the
// property that keeps chunk textures seamless.
TEST(ResampleTile, NeighboursShareTheirBorderAfterResampling) {
  for (uint32_t n : {5u, 17u, 33u}) {
    TexelTile a = randomTile(n, 3, 100 + n), b = randomTile(n, 3, 200 + n);
    TexelTile c = randomTile(n, 3, 300 + n);  // north of a
    for (uint32_t k = 0; k < n; ++k) {
      std::memcpy(b.at(0, k), a.at(n - 1, k), 3 * sizeof(float));  // a's east = b's west
      std::memcpy(c.at(k, 0), a.at(k, n - 1), 3 * sizeof(float));  // a's north = c's south
    }
    ASSERT_NE(a.at(1, 1)[0], b.at(1, 1)[0]);  // the interiors differ
    for (uint32_t to : kSizes) {
      const TexelTile ra = resampleTile(a, to), rb = resampleTile(b, to), rc = resampleTile(c, to);
      for (uint32_t k = 0; k < to; ++k)
        for (int ch = 0; ch < 3; ++ch) {
          ASSERT_TRUE(bitwiseEqual(ra.at(to - 1, k)[ch], rb.at(0, k)[ch]))
              << n << " -> " << to << " east/west texel " << k;
          ASSERT_TRUE(bitwiseEqual(ra.at(k, to - 1)[ch], rc.at(k, 0)[ch]))
              << n << " -> " << to << " north/south texel " << k;
        }
    }
  }
}

// The same through the whole quadtree: sibling leaves that share borders are mosaicked into
// parents, which are resampled, then mosaicked into a grandparent and resampled again; the
// two grandparents side by side still share their border, at every step of a mip chain too.
TEST(ResampleTile, NeighboursShareTheirBorderThroughMosaicsAndMips) {
  const uint32_t n = 17;
  // A 8x4 grid of leaves cut from one random field of 8*16+1 x 4*16+1 texels.
  const TexelTile field = randomTile(8 * (n - 1) + 1, 2, 77);
  auto leaf = [&](uint32_t ix, uint32_t iy) {
    TexelTile t(n, 2);
    for (uint32_t y = 0; y < n; ++y)
      for (uint32_t x = 0; x < n; ++x)
        std::memcpy(t.at(x, y), field.at(ix * (n - 1) + x, iy * (n - 1) + y), 2 * sizeof(float));
    return t;
  };
  std::function<TexelTile(uint32_t, uint32_t, uint32_t)> node = [&](uint32_t level, uint32_t ix,
                                                                    uint32_t iy) {
    if (level == 0) return leaf(ix, iy);
    const TexelTile sw = node(level - 1, 2 * ix, 2 * iy), se = node(level - 1, 2 * ix + 1, 2 * iy),
                    nw = node(level - 1, 2 * ix, 2 * iy + 1),
                    ne = node(level - 1, 2 * ix + 1, 2 * iy + 1);
    return resampleTile(mosaicTiles({&sw, &se, &nw, &ne}), n);
  };
  TexelTile west = node(2, 0, 0), east = node(2, 1, 0);
  while (true) {
    for (uint32_t k = 0; k < west.size; ++k)
      for (int ch = 0; ch < 2; ++ch)
        ASSERT_TRUE(bitwiseEqual(west.at(west.size - 1, k)[ch], east.at(0, k)[ch]))
            << "size " << west.size << " texel " << k;
    if (west.size <= 2) break;
    west = resampleTile(west, west.size / 2);  // the mip chain's sizes
    east = resampleTile(east, east.size / 2);
  }
}

// ---------------------------------------------------------------------------------------------
// mosaicTiles

// A field of (2n - 1)^2 texels and its four quadrants, which share their borders.
struct Quadrants {
  TexelTile field;
  std::array<TexelTile, 4> tiles;  // SW, SE, NW, NE
};

Quadrants quadrants(uint32_t n, uint32_t channels, uint32_t seed) {
  Quadrants q{randomTile(2 * n - 1, channels, seed), {}};
  for (uint32_t k = 0; k < 4; ++k) {
    q.tiles[k] = TexelTile(n, channels);
    const uint32_t ox = (k & 1) * (n - 1), oy = (k >> 1) * (n - 1);
    for (uint32_t y = 0; y < n; ++y)
      for (uint32_t x = 0; x < n; ++x)
        std::memcpy(q.tiles[k].at(x, y), q.field.at(ox + x, oy + y), channels * sizeof(float));
  }
  return q;
}

TEST(MosaicTiles, FourChildrenMakeOneTileOfTwiceTheCellsAndKeepEveryTexel) {
  for (uint32_t n : {2u, 5u, 17u}) {
    const Quadrants q = quadrants(n, 3, n);
    const TexelTile m = mosaicTiles({&q.tiles[0], &q.tiles[1], &q.tiles[2], &q.tiles[3]});
    ASSERT_EQ(m.size, 2 * n - 1);
    ASSERT_EQ(m.channels, 3u);
    EXPECT_EQ(m.values, q.field.values) << n;
  }
}

TEST(MosaicTiles, ChildrenLandInTheirQuadrants) {
  // Children of distinct constant values (disagreeing borders): each child's texels that no
  // other child overlaps sit at its offset, SW at (0, 0), SE at (n-1, 0), NW at (0, n-1), NE
  // at (n-1, n-1).
  const uint32_t n = 5;
  std::array<TexelTile, 4> tiles;
  for (uint32_t k = 0; k < 4; ++k) {
    tiles[k] = TexelTile(n, 1);
    for (uint32_t y = 0; y < n; ++y)
      for (uint32_t x = 0; x < n; ++x) tiles[k].at(x, y)[0] = float(10 * (k + 1) + y * n + x);
  }
  const TexelTile m = mosaicTiles({&tiles[0], &tiles[1], &tiles[2], &tiles[3]});
  ASSERT_EQ(m.size, 2 * n - 1);
  for (uint32_t y = 0; y < m.size; ++y)
    for (uint32_t x = 0; x < m.size; ++x) {
      const uint32_t k = (x > n - 1 ? 1 : 0) + (y > n - 1 ? 2 : 0);
      const uint32_t lx = x - (k & 1) * (n - 1), ly = y - (k >> 1) * (n - 1);
      if ((x == n - 1) || (y == n - 1)) continue;  // shared texels: any child's value
      EXPECT_EQ(m.at(x, y)[0], tiles[k].at(lx, ly)[0]) << x << "," << y;
    }
}

TEST(MosaicTiles, MissingChildrenRepeatTheNearestTexels) {
  const uint32_t n = 5, e = n - 1;
  const Quadrants q = quadrants(n, 2, 9);
  const TexelTile *sw = &q.tiles[0], *se = &q.tiles[1], *nw = &q.tiles[2];
  struct MissingCase {
    const char* name;
    std::array<const TexelTile*, 4> children;
    bool east, north;  // which halves exist
  };
  for (const MissingCase& c :
       {MissingCase{"SW only", {sw, nullptr, nullptr, nullptr}, false, false},
        MissingCase{"SW+SE", {sw, se, nullptr, nullptr}, true, false},
        MissingCase{"SW+NW", {sw, nullptr, nw, nullptr}, false, true}}) {
    const TexelTile m = mosaicTiles(c.children);
    ASSERT_EQ(m.size, 2 * n - 1) << c.name;
    for (uint32_t y = 0; y < m.size; ++y)
      for (uint32_t x = 0; x < m.size; ++x) {
        const uint32_t fx = c.east ? x : std::min(x, e), fy = c.north ? y : std::min(y, e);
        for (int ch = 0; ch < 2; ++ch)
          ASSERT_EQ(m.at(x, y)[ch], q.field.at(fx, fy)[ch]) << c.name << " at " << x << "," << y;
      }
  }
}

TEST(MosaicBuilder, ChildrenAddedOneAtATimeGiveTheSameFloatsInAnyOrder) {
  const uint32_t n = 33;
  std::array<TexelTile, 4> t;
  for (uint32_t q = 0; q < 4; ++q) t[q] = randomTile(n, 3, 60 + q);
  for (const std::array<bool, 4> present :
       {std::array{true, true, true, true}, std::array{true, false, false, false},
        std::array{true, true, false, false}, std::array{true, false, true, false}}) {
    std::array<const TexelTile*, 4> children{};
    std::vector<size_t> order;
    for (size_t q = 0; q < 4; ++q)
      if (present[q]) children[q] = &t[q], order.push_back(q);
    for (uint32_t size : {2 * n - 1, n, 17u, 9u, 2u}) {
      const TexelTile expected = resampleTile(mosaicTiles(children), size);
      do {
        SCOPED_TRACE(testing::Message()
                     << order.size() << " children, first " << order[0] << ", to " << size);
        // Children lent (the const overload) and given (the one that may keep them).
        for (bool given : {false, true}) {
          MosaicBuilder builder(n, 3, size, present);
          for (size_t q : order) {
            if (given)
              builder.add(q, TexelTile(t[q]));
            else
              builder.add(q, t[q]);
          }
          const TexelTile got = builder.finish();
          ASSERT_EQ(got.size, expected.size);
          ASSERT_EQ(got.values.size(), expected.values.size());
          for (size_t i = 0; i < got.values.size(); ++i)
            ASSERT_TRUE(bitwiseEqual(got.values[i], expected.values[i]))
                << "value " << i << (given ? " given" : " lent");
        }
      } while (std::next_permutation(order.begin(), order.end()));
    }
  }
}

// ---------------------------------------------------------------------------------------------
// planTextures

bool powerOfTwoPlusOne(uint32_t s) {
  return s >= 3 && ((s - 1) & (s - 2)) == 0;
}

void checkPlan(const TreeLayout& layout, double leafError, double sx, double sy, double tau,
               uint32_t refine) {
  SCOPED_TRACE(testing::Message() << "leafError " << leafError << " spacing " << sx << "x" << sy
                                  << " tau " << tau << " refine " << refine);
  const std::vector<double> errors = levelErrors(layout, leafError);
  const std::vector<TextureLevel> plan = planTextures(layout, errors, sx, sy, tau, refine);
  ASSERT_EQ(plan.size(), size_t(layout.levelCount()));
  for (int32_t level = 0; level < layout.levelCount(); ++level) {
    SCOPED_TRACE(testing::Message() << "level " << level);
    const TextureLevel& t = plan[size_t(level)];
    const uint32_t cells = uint32_t(layout.chunkCells(level));
    const double side = cells * std::max(sx, sy), texel = errors[size_t(level)] / tau;
    struct Layer {
      uint32_t size;
      uint8_t flags;
      uint32_t cap;
    };
    for (const Layer& l : {Layer{t.normalSize, t.normalFlags, cells},
                           Layer{t.colorSize, t.colorFlags, cells * refine}}) {
      EXPECT_TRUE(powerOfTwoPlusOne(l.size)) << l.size;
      EXPECT_GE(l.size, 5u);
      EXPECT_LE(l.size - 1, l.cap);
      if (l.flags & kTextureSourceLimited) {
        EXPECT_EQ(l.size - 1, l.cap);                        // capped at the source's texels
        EXPECT_GT(side / (l.size - 1), texel * (1 + 1e-9));  // and only when that is too coarse
      } else {
        EXPECT_EQ(l.flags, 0);
        EXPECT_LE(side / (l.size - 1), texel * (1 + 1e-9));  // eq. 7
        if (l.size > 5) {                                    // the smallest such power of two
          EXPECT_GT(side / ((l.size - 1) / 2), texel * (1 + 1e-9));
        }
      }
    }
  }
}

TEST(PlanTextures, SizesMeetEq7OrAreCappedBySource) {
  auto layout = makeTreeLayout(1025, 777, 64);  // roots of 1024 cells, levels 0..4
  ASSERT_TRUE(layout.ok());
  ASSERT_EQ(layout->depth, 4);
  for (double leafError : {0.25, 1.0, 7.5, 30.0, 120.0, 1000.0})
    for (auto [sx, sy] : {std::pair{30.0, 30.0}, std::pair{2.0, 3.0}})
      for (double tau : {1.0, kDefaultTextureTau, 4.0})
        for (uint32_t refine : {1u, 2u, 4u}) checkPlan(*layout, leafError, sx, sy, tau, refine);
}

TEST(PlanTextures, KnownSizes) {
  auto layout = makeTreeLayout(1025, 1025, 64);
  ASSERT_TRUE(layout.ok());
  // 30 m cells, leaf error 30 m, τ 2: texels of 15 m, so 128 intervals per chunk at every
  // level; the leaves (64 cells) and nothing else are capped at one texel per cell.
  const auto plan = planTextures(*layout, levelErrors(*layout, 30.0), 30, 30, 2.0, 1);
  ASSERT_EQ(plan.size(), 5u);
  for (int level = 0; level < 4; ++level) {
    EXPECT_EQ(plan[level].normalSize, 129u) << level;
    EXPECT_EQ(plan[level].normalFlags, 0) << level;
    EXPECT_EQ(plan[level].colorSize, 129u) << level;
  }
  EXPECT_EQ(plan[4].normalSize, 65u);
  EXPECT_EQ(plan[4].normalFlags, kTextureSourceLimited);
  EXPECT_EQ(plan[4].colorSize, 65u);
  EXPECT_EQ(plan[4].colorFlags, kTextureSourceLimited);
  // With an image twice as fine as the DEM the leaves' colour gets its 128 intervals.
  const auto refined = planTextures(*layout, levelErrors(*layout, 30.0), 30, 30, 2.0, 2);
  EXPECT_EQ(refined[4].normalSize, 65u);
  EXPECT_EQ(refined[4].colorSize, 129u);
  EXPECT_EQ(refined[4].colorFlags, 0);
  // Coarse errors: the minimum of 4 intervals.
  const auto coarse = planTextures(*layout, levelErrors(*layout, 1e4), 30, 30, 2.0, 1);
  for (const TextureLevel& t : coarse) {
    EXPECT_EQ(t.normalSize, 5u);
    EXPECT_EQ(t.colorSize, 5u);
  }
}

TEST(PlanTextures, FineErrorsAreSourceLimitedAndRefineDoublesTheColourCap) {
  auto layout = makeTreeLayout(1025, 1025, 64);
  ASSERT_TRUE(layout.ok());
  const auto errors = levelErrors(*layout, 0.5);  // far finer than 30 m cells can show
  const auto one = planTextures(*layout, errors, 30, 30, 2.0, 1);
  const auto two = planTextures(*layout, errors, 30, 30, 2.0, 2);
  for (int32_t level = 0; level < layout->levelCount(); ++level) {
    const uint32_t cells = uint32_t(layout->chunkCells(level));
    EXPECT_EQ(one[level].normalSize, cells + 1) << level;
    EXPECT_EQ(one[level].normalFlags, kTextureSourceLimited) << level;
    EXPECT_EQ(one[level].colorSize, cells + 1) << level;
    EXPECT_EQ(one[level].colorFlags, kTextureSourceLimited) << level;
    EXPECT_EQ(two[level].normalSize, cells + 1) << level;
    EXPECT_EQ(two[level].colorSize, 2 * cells + 1) << level;
    EXPECT_EQ(two[level].colorFlags, kTextureSourceLimited) << level;
  }
}

TEST(PlanTextures, HardCapAtMaxTextureSize) {
  auto layout = makeTreeLayout(8193, 8193, 64);  // roots of 8192 cells
  ASSERT_TRUE(layout.ok());
  const auto plan = planTextures(*layout, levelErrors(*layout, 0.01), 30, 30, 2.0, 4);
  EXPECT_EQ(plan[0].normalSize, kMaxTextureSize);
  EXPECT_EQ(plan[0].normalFlags, kTextureSourceLimited);
  EXPECT_EQ(plan[0].colorSize, kMaxTextureSize);
  for (const TextureLevel& t : plan) {
    EXPECT_LE(t.normalSize, kMaxTextureSize);
    EXPECT_LE(t.colorSize, kMaxTextureSize);
  }
}

// ---------------------------------------------------------------------------------------------
// BlockTexels: normals against analytic surfaces

// Heights of an analytic surface z = f(x, y) in metres at grid point (gx * sx, gy * sy),
// everywhere (no edge replication).
class AnalyticHeights final : public HeightWindows {
 public:
  AnalyticHeights(double sx, double sy, std::function<double(double, double)> f)
      : mSx(sx), mSy(sy), mF(std::move(f)) {}
  Status read(int32_t x0, int32_t y0, int32_t w, int32_t h, float* out, unsigned) override {
    for (int32_t y = 0; y < h; ++y)
      for (int32_t x = 0; x < w; ++x)
        out[size_t(y) * w + x] = float(mF((x0 + x) * mSx, (y0 + y) * mSy));
    return {};
  }

 private:
  double mSx, mSy;
  std::function<double(double, double)> mF;
};

TEST(BlockTexels, NormalsOfAPlane) {
  const double sx = 2, sy = 3;
  AnalyticHeights plane(sx, sy, [](double x, double y) { return 0.3 * x + 0.1 * y + 50; });
  SurfaceTexelOptions options;
  options.spacingX = sx;
  options.spacingY = sy;
  BlockTexels texels(options);
  const int32_t x0 = 12, y0 = 20, cells = 32;
  ASSERT_TRUE(texels.load(plane, 0, nullptr, x0, y0, cells).ok());
  const double len = std::sqrt(0.3 * 0.3 + 0.1 * 0.1 + 1);
  const double expected[3] = {-0.3 / len, -0.1 / len, 1 / len};
  // The whole block and a chunk inside it.
  for (auto [cx, cy, cc] : {std::tuple{x0, y0, cells}, std::tuple{x0 + 8, y0 + 16, 16}}) {
    const TexelTile n = texels.normals(cx, cy, cc);
    ASSERT_EQ(n.size, uint32_t(cc + 1));
    ASSERT_EQ(n.channels, 3u);
    for (uint32_t j = 0; j < n.size; ++j)
      for (uint32_t i = 0; i < n.size; ++i)
        for (int c = 0; c < 3; ++c)
          ASSERT_NEAR(n.at(i, j)[c], expected[c], 1e-5) << i << "," << j << " channel " << c;
  }
}

// z = A sin(kx x) + B sin(ky y). Central differences over h give the slope times
// sin(k h) / (k h), so the slope is off by at most A kx (kx sx)² / 6 along x (B ky (ky sy)² / 6
// along y); the unit normal as a function of the slope is 1-Lipschitz, so the normal is off by
// at most the length of that slope error (plus float rounding of the heights).
TEST(BlockTexels, NormalsOfASineSurfaceMatchTheAnalyticNormal) {
  const double sx = 2, sy = 3, A = 20, B = 12, kx = 2 * M_PI / 160, ky = 2 * M_PI / 210;
  AnalyticHeights sine(sx, sy, [&](double x, double y) {
    return 100 + A * std::sin(kx * x) + B * std::sin(ky * y);
  });
  SurfaceTexelOptions options;
  options.spacingX = sx;
  options.spacingY = sy;
  BlockTexels texels(options);
  const int32_t x0 = 0, y0 = 64, cells = 128;  // more than a wavelength each way
  ASSERT_TRUE(texels.load(sine, 0, nullptr, x0, y0, cells).ok());
  const double ex = A * kx * std::pow(kx * sx, 2) / 6, ey = B * ky * std::pow(ky * sy, 2) / 6;
  const double bound = std::hypot(ex, ey) + 1e-5;  // 1e-5: float heights (ulp of ~130 / 4 m)
  const TexelTile n = texels.normals(x0, y0, cells);
  double worst = 0;
  for (uint32_t j = 0; j < n.size; ++j)
    for (uint32_t i = 0; i < n.size; ++i) {
      const double x = (x0 + int32_t(i)) * sx, y = (y0 + int32_t(j)) * sy;
      const double px = A * kx * std::cos(kx * x), py = B * ky * std::cos(ky * y);
      const double len = std::sqrt(px * px + py * py + 1);
      const double d = std::hypot(n.at(i, j)[0] - (-px / len), n.at(i, j)[1] - (-py / len),
                                  n.at(i, j)[2] - 1 / len);
      worst = std::max(worst, d);
      ASSERT_LE(d, bound) << i << "," << j;
      ASSERT_NEAR(std::hypot(n.at(i, j)[0], n.at(i, j)[1], n.at(i, j)[2]), 1.0, 1e-6);
    }
  // The bound is tight: the error measured is the central differences' own.
  EXPECT_GT(worst, 0.5 * (bound - 1e-5));
}

// Neighbouring blocks compute their shared border texels identically (each from its own
// window), so leaves of different blocks meet without a seam.
TEST(BlockTexels, NeighbouringBlocksAgreeOnTheirSharedBorder) {
  const Heightfield h = test::makeTestTerrain(100, 90, 3);
  MemoryHeights heights(h);
  SurfaceTexelOptions options;
  options.spacingX = 10;
  options.spacingY = 12;
  BlockTexels a(options), b(options), c(options);
  const int32_t cells = 32;
  ASSERT_TRUE(a.load(heights, 0, nullptr, 32, 32, cells).ok());
  ASSERT_TRUE(b.load(heights, 0, nullptr, 64, 32, cells).ok());  // east of a
  ASSERT_TRUE(c.load(heights, 0, nullptr, 32, 64, cells).ok());  // north of a
  for (bool color : {false, true}) {
    auto tile = [&](const BlockTexels& t, int32_t x0, int32_t y0) {
      return color ? t.colors(x0, y0, cells) : t.normals(x0, y0, cells);
    };
    const TexelTile ta = tile(a, 32, 32), tb = tile(b, 64, 32), tc = tile(c, 32, 64);
    ASSERT_EQ(ta.size, uint32_t(cells + 1));
    for (uint32_t k = 0; k <= uint32_t(cells); ++k)
      for (int ch = 0; ch < 3; ++ch) {
        ASSERT_TRUE(bitwiseEqual(ta.at(cells, k)[ch], tb.at(0, k)[ch])) << color << " " << k;
        ASSERT_TRUE(bitwiseEqual(ta.at(k, cells)[ch], tc.at(k, 0)[ch])) << color << " " << k;
      }
    if (color)
      for (float v : ta.values) {
        EXPECT_GE(v, 0.0f);
        EXPECT_LE(v, 1.0f);
      }
  }
}

// With an image drape the colour tile is the image's texels, refine per cell, blended by
// their alpha over the generated colour resampled to the same size.
TEST(BlockTexels, ColoursComeFromTheDrapedImage) {
  auto dem = DemReader::open(test::testData("zion_srtm3.tif"), {});  // geographic, 3"
  ASSERT_TRUE(dem.ok()) << dem.error().message;
  auto image = ImageDrape::open(test::testData("zion_landsat8_rgb_utm12_30m.tif"), (*dem)->info());
  ASSERT_TRUE(image.ok()) << image.error().message;
  const ImageDrape& drape = **image;
  const uint32_t r = drape.refine();
  ASSERT_EQ(r, 2u);
  const Heightfield h = test::makeTestTerrain(465, 457, 6);
  MemoryHeights heights(h);
  SurfaceTexelOptions options;
  options.spacingX = (*dem)->info().spacingX;
  options.spacingY = (*dem)->info().spacingY;
  // A block on the DEM's western edge, which the UTM image does not quite reach.
  const int32_t x0 = 0, y0 = 192, cells = 32;
  BlockTexels withImage(options), without(options);
  ASSERT_TRUE(withImage.load(heights, 0, &drape, x0, y0, cells).ok());
  ASSERT_TRUE(without.load(heights, 0, nullptr, x0, y0, cells).ok());
  int transparent = 0, opaque = 0;
  // The block and a chunk inside it.
  for (auto [cx, cy, cc] : {std::tuple{x0, y0, cells}, std::tuple{x0 + 16, y0 + 8, 16}}) {
    const TexelTile tile = withImage.colors(cx, cy, cc);
    const uint32_t size = uint32_t(cc) * r + 1;
    ASSERT_EQ(tile.size, size);
    ASSERT_EQ(tile.channels, 3u);
    const TexelTile fallback = resampleTile(without.colors(cx, cy, cc), size);
    std::vector<uint8_t> rgba(size_t(size) * size * 4);
    ASSERT_TRUE(
        drape.read(int64_t(cx) * r, int64_t(cy) * r, int32_t(size), int32_t(size), rgba.data())
            .ok());
    for (uint32_t j = 0; j < size; ++j)
      for (uint32_t i = 0; i < size; ++i) {
        const uint8_t* p = &rgba[(size_t(j) * size + i) * 4];
        const float a = p[3] / 255.0f;
        transparent += p[3] == 0;
        opaque += p[3] == 255;
        for (int c = 0; c < 3; ++c)
          ASSERT_NEAR(tile.at(i, j)[c], a * p[c] / 255.0f + (1 - a) * fallback.at(i, j)[c], 1e-6)
              << cc << " cells: " << i << "," << j << " channel " << c;
      }
  }
  EXPECT_GT(transparent, 100);  // both cases occur
  EXPECT_GT(opaque, 100);
}

// ---------------------------------------------------------------------------------------------
// Encoders: decode the stored BC5 / BC1 blocks by hand (tests/support/bc_decode.h, written
// from the format specifications).

// Normal (x, y) of a decoded BC5 mip level of `size` texels.
std::array<double, 3> decodedNormal(const std::vector<uint8_t>& rg, uint32_t size, uint32_t x,
                                    uint32_t y) {
  const size_t k = (size_t(y) * size + x) * 2;
  return test::normalFromRg8(rg[k], rg[k + 1]);
}

void checkLayerShape(const TextureLayer& l, TextureLayerKind kind, TextureEncoding encoding,
                     uint32_t size, uint8_t flags) {
  EXPECT_EQ(l.kind, kind);
  EXPECT_EQ(l.encoding, encoding);
  EXPECT_EQ(l.size, size);
  EXPECT_EQ(l.flags, flags);
  ASSERT_EQ(l.mips.size(), mipCount(size));
  for (uint32_t m = 0; m < l.mips.size(); ++m)
    EXPECT_EQ(l.mips[m].size(), mipBytes(encoding, size, m)) << m;
  // And the layer goes through the codec as it is.
  ChunkTexture t;
  t.layers.push_back(l);
  auto decoded = decodeTexture(encodeTexture(t, 3), "test");
  ASSERT_TRUE(decoded.ok()) << decoded.error().message;
  EXPECT_EQ(decoded->layers[0].mips, l.mips);
}

// alpha_block.h's BC4 and BC5 encoders, vector and portable, give stb_dxt's bytes: on random
// blocks of every range (constant, narrow, both sides of the 8-step rounding change, full).
TEST(TextureEncoder, AlphaBlocksAreStbDxtsBytes) {
  std::mt19937 rng(7);
  int differing = 0, blocks = 0;
  for (int range : {0, 1, 2, 3, 7, 8, 9, 15, 16, 40, 100, 255})
    for (int trial = 0; trial < 2000; ++trial) {
      const int lo = int(rng() % uint32_t(256 - range));
      uint8_t texels[32];
      for (uint8_t& t : texels) t = uint8_t(lo + (range ? int(rng() % uint32_t(range + 1)) : 0));
      uint8_t theirs4[8], theirs5[16], ours[16];
      stb_compress_bc4_block(theirs4, texels);
      stb_compress_bc5_block(theirs5, texels);
      encodeBc4Block(ours, texels);
      differing += std::memcmp(ours, theirs4, 8) != 0;
      encodeAlphaBlockPortable<1>(ours, texels);
      differing += std::memcmp(ours, theirs4, 8) != 0;
      encodeBc5Block(ours, texels);
      differing += std::memcmp(ours, theirs5, 16) != 0;
      encodeAlphaBlockPortable<2>(ours, texels);
      encodeAlphaBlockPortable<2>(ours + 8, texels + 1);
      differing += std::memcmp(ours, theirs5, 16) != 0;
      blocks += 4;
    }
  EXPECT_EQ(differing, 0) << "of " << blocks;
}

// The texel-to-byte conversions give the portable loops' bytes, on lengths that leave a
// remainder for the scalar tail, with values beyond [0, 1], zero normals and long ones.
TEST(TextureEncoder, TexelBytesAreThePortableLoopsBytes) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> wide(-1.5f, 2.5f), normal(-4.0f, 4.0f);
  for (size_t n : {size_t(1), size_t(15), size_t(16), size_t(17), size_t(1089)}) {
    std::vector<float> units(n), normals(3 * n);
    for (float& v : units) v = wide(rng);
    for (float& v : normals) v = normal(rng);
    for (size_t i = 0; i < n; i += 7) std::fill_n(normals.begin() + ptrdiff_t(3 * i), 3, 0.0f);
    std::vector<uint8_t> fast(2 * n), portable(2 * n);
    unitsToBytes(units.data(), n, fast.data());
    texel_bytes::unitsToBytesPortable(units.data(), n, portable.data());
    EXPECT_EQ(std::vector<uint8_t>(fast.begin(), fast.begin() + ptrdiff_t(n)),
              std::vector<uint8_t>(portable.begin(), portable.begin() + ptrdiff_t(n)))
        << n;
    normalsToRg(normals.data(), n, fast.data());
    texel_bytes::normalsToRgPortable(normals.data(), n, portable.data());
    EXPECT_EQ(fast, portable) << n;
  }
  uint8_t rg[2];
  const float zero[3] = {0, 0, 0}, east[3] = {3, 0, 0};
  normalToRg(zero, rg);
  EXPECT_EQ(rg[0], 128);
  EXPECT_EQ(rg[1], 128);
  normalToRg(east, rg);
  EXPECT_EQ(rg[0], 255);
  EXPECT_EQ(rg[1], 128);
  EXPECT_EQ(unitToByte(-0.2f), 0);
  EXPECT_EQ(unitToByte(1.7f), 255);
}

TEST(TextureEncoder, NormalLayerOfAPlaneDecodesToItsNormal) {
  const double sx = 2, sy = 3;
  AnalyticHeights plane(sx, sy, [](double x, double y) { return 0.3 * x + 0.1 * y; });
  SurfaceTexelOptions options;
  options.spacingX = sx;
  options.spacingY = sy;
  BlockTexels texels(options);
  ASSERT_TRUE(texels.load(plane, 0, nullptr, 0, 0, 32).ok());
  const TexelTile tile = texels.normals(0, 0, 32);
  const TextureLayer layer = encodeNormalLayer(tile, kTextureSourceLimited);
  checkLayerShape(layer, TextureLayerKind::kNormal, TextureEncoding::kBc5, 33,
                  kTextureSourceLimited);
  const double len = std::sqrt(0.3 * 0.3 + 0.1 * 0.1 + 1);
  const double expected[3] = {-0.3 / len, -0.1 / len, 1 / len};
  for (uint32_t m = 0; m < layer.mips.size(); ++m) {  // mip 0 and, the plane being flat, all
    const uint32_t s = mipSize(33, m);
    const std::vector<uint8_t> rg = test::decodeBc5Layer(layer.mips[m], s);
    ASSERT_EQ(rg.size(), size_t(s) * s * 2) << "mip " << m;
    for (uint32_t y = 0; y < s; ++y)
      for (uint32_t x = 0; x < s; ++x) {
        const auto n = decodedNormal(rg, s, x, y);
        for (int c = 0; c < 3; ++c)
          ASSERT_NEAR(n[size_t(c)], expected[c], 0.02) << "mip " << m << " " << x << "," << y;
      }
  }
}

// Normals that vary across the tile (x with the column, y with the row): every texel decodes
// to its own normal, which checks the block and texel order as well as the channels. Input
// normals need not be unit length.
TEST(TextureEncoder, NormalLayerKeepsEveryTexelInPlace) {
  const uint32_t size = 33;
  TexelTile tile(size, 3);
  auto normal = [&](uint32_t x, uint32_t y) {
    const double px = 0.8 * (double(x) / (size - 1) - 0.3),
                 py = -0.6 * (double(y) / (size - 1) - 0.6);
    const double len = std::sqrt(px * px + py * py + 1);
    return std::array<double, 3>{-px / len, -py / len, 1 / len};
  };
  for (uint32_t y = 0; y < size; ++y)
    for (uint32_t x = 0; x < size; ++x)
      for (int c = 0; c < 3; ++c) tile.at(x, y)[c] = float(3.0 * normal(x, y)[size_t(c)]);
  const TextureLayer layer = encodeNormalLayer(tile, 0);
  checkLayerShape(layer, TextureLayerKind::kNormal, TextureEncoding::kBc5, size, 0);
  const std::vector<uint8_t> rg = test::decodeBc5Layer(layer.mips[0], size);
  ASSERT_EQ(rg.size(), size_t(size) * size * 2);
  for (uint32_t y = 0; y < size; ++y)
    for (uint32_t x = 0; x < size; ++x) {
      const auto n = decodedNormal(rg, size, x, y);
      for (int c = 0; c < 3; ++c)
        ASSERT_NEAR(n[size_t(c)], normal(x, y)[size_t(c)], 0.02) << x << "," << y << " " << c;
    }
}

TEST(TextureEncoder, ColorLayerOfAConstantColour) {
  const float rgb[3] = {0.8f, 0.4f, 0.1f};
  for (uint32_t size : {5u, 17u, 65u}) {
    TexelTile tile(size, 3);
    for (uint32_t i = 0; i < size * size; ++i) std::memcpy(&tile.values[i * 3], rgb, sizeof rgb);
    const TextureLayer layer = encodeColorLayer(tile, 0);
    checkLayerShape(layer, TextureLayerKind::kColor, TextureEncoding::kBc1, size, 0);
    for (uint32_t m = 0; m < layer.mips.size(); ++m) {
      const uint32_t s = mipSize(size, m);
      const std::vector<uint8_t> texels = test::decodeBc1Layer(layer.mips[m], s);
      ASSERT_EQ(texels.size(), size_t(s) * s * 3) << "size " << size << " mip " << m;
      for (uint32_t y = 0; y < s; ++y)
        for (uint32_t x = 0; x < s; ++x) {
          const uint8_t* texel = &texels[(size_t(y) * s + x) * 3];
          for (int c = 0; c < 3; ++c)
            ASSERT_NEAR(texel[c], rgb[c] * 255.0, 4.0)
                << "size " << size << " mip " << m << " " << x << "," << y << " channel " << c;
        }
    }
  }
}

// Colours along one line in RGB space (BC1's model of a block), varying across the tile:
// every texel decodes close to its own colour.
TEST(TextureEncoder, ColorLayerKeepsEveryTexelInPlace) {
  const uint32_t size = 33;
  TexelTile tile(size, 3);
  auto color = [&](uint32_t x, uint32_t y) {
    const double s = 0.5 * x / (size - 1) + 0.3 * y / (size - 1);
    return std::array<double, 3>{0.2 + 0.6 * s, 0.3 + 0.4 * s, 0.7 - 0.5 * s};
  };
  for (uint32_t y = 0; y < size; ++y)
    for (uint32_t x = 0; x < size; ++x)
      for (int c = 0; c < 3; ++c) tile.at(x, y)[c] = float(color(x, y)[size_t(c)]);
  const TextureLayer layer = encodeColorLayer(tile, kTextureSourceLimited);
  checkLayerShape(layer, TextureLayerKind::kColor, TextureEncoding::kBc1, size,
                  kTextureSourceLimited);
  const std::vector<uint8_t> texels = test::decodeBc1Layer(layer.mips[0], size);
  ASSERT_EQ(texels.size(), size_t(size) * size * 3);
  for (uint32_t y = 0; y < size; ++y)
    for (uint32_t x = 0; x < size; ++x) {
      const uint8_t* texel = &texels[(size_t(y) * size + x) * 3];
      for (int c = 0; c < 3; ++c)
        ASSERT_NEAR(texel[c], color(x, y)[size_t(c)] * 255.0, 6.0)
            << x << "," << y << " channel " << c;
    }
}

}  // namespace
}  // namespace terralod
