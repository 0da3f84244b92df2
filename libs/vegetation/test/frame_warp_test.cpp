#include "terralod/vegetation/frame_warp.h"

#include <gtest/gtest.h>

#include <cmath>
#include <map>

#include "terralod/vegetation/ldi_camera.h"

namespace terralod::veg {
namespace {

// A tile of posts: a column of opaque depth pixels at a few places, each at a known height,
// seen by a top-down LDI (so a post is one pixel with one layer per height step).
WarpLdi posts(uint32_t n, float tileSize, uint32_t colour) {
  Ldi ldi;
  ldi.camera.width = ldi.camera.height = n;
  ldi.camera.pixelSize = tileSize / float(n);
  ldi.camera.origin = {0, 0, 3};
  ldi.camera.direction = {0, 0, -1};
  ldi.camera.depthMin = 0;
  ldi.camera.depthMax = 3;
  ldi.layerCounts.assign(size_t(n) * n, 0);
  const uint32_t up = encodeSplatNormal({0, 0, 1});
  for (uint32_t r = 0; r < n; ++r)
    for (uint32_t c = 0; c < n; ++c) {
      if ((r * 7 + c * 3) % 5 != 0) continue;
      ldi.layerCounts[size_t(r) * n + c] = 3;
      for (int k = 0; k < 3; ++k) {  // 2.5, 2 and 1.5 m below the image plane
        const float depth = 1.5f + 0.5f * float(k);
        ldi.pixels.push_back(
            DepthPixel::make(colour + uint32_t(k) * 40, uint32_t(depth / 3.0f * kLdiMaxDepth), up));
      }
    }
  return WarpLdi::of(std::move(ldi));
}

class TwoLdis final : public LdiSource {
 public:
  const WarpLdi* ldi(int prototile, int, int) override { return &mLdis[prototile % 2]; }
  uint64_t depthPixels(int prototile, int, int) const override {
    return mLdis[prototile % 2].ldi.pixels.size();
  }
  WarpLdi mLdis[2] = {posts(40, 4, 0xff2040c0), posts(40, 4, 0xff30a020)};
};

View viewFrom(glm::dvec3 eye, glm::dvec3 target) {
  Camera c;
  c.eye = eye;
  c.target = target;
  c.width = 320;
  c.height = 240;
  return makeView(c).value();
}

std::vector<TileDraw> field(const View& view) {
  std::vector<TileDraw> tiles;
  for (uint32_t y = 0; y < 12; ++y)
    for (uint32_t x = 0; x < 12; ++x) {
      TileDraw t;
      t.x = x;
      t.y = y;
      t.prototile = int(x + y);
      t.ldis[0] = {0, 0, 1.0f};
      t.ldiCount = 1;
      t.placement = {glm::vec2(4.0f * float(x), 4.0f * float(y)),
                     4.0f,
                     {0.1f * float(x), 0.1f * float(x + 1), 0.1f * float(x + 1), 0.1f * float(x)}};
      t.distance = glm::length(glm::dvec3(4.0 * x + 2, 4.0 * y + 2, 1) - view.camera.eye);
      t.screenPixels = 4.0 * view.pixelsPerRadian / t.distance;
      tiles.push_back(t);
    }
  std::sort(tiles.begin(), tiles.end(),
            [](const TileDraw& a, const TileDraw& b) { return a.distance > b.distance; });
  return tiles;
}

struct Picture {
  std::vector<uint32_t> rgba;
  std::vector<float> depth;
  FrameWarpStats stats;
};

Picture paint(const View& view, unsigned threads) {
  TwoLdis ldis;
  Picture p;
  const int w = view.camera.width, h = view.camera.height;
  p.rgba.assign(size_t(w) * h, 0xdeadbeef);
  p.depth.assign(size_t(w) * h, -1.0f);
  FrameWarper warper;
  FrameWarpOptions o;
  o.threads = threads;
  p.stats = warper.warp(field(view), ldis, view, o, {w, h, p.rgba, p.depth});
  return p;
}

TEST(FrameWarp, ThreadsAndTheirMergeMakeTheSamePictureAsOneThread) {
  const View view = viewFrom({20, -6, 5}, {24, 30, 0});
  const Picture one = paint(view, 1), three = paint(view, 3);
  EXPECT_EQ(one.stats.tiles, 144u);
  EXPECT_GT(one.stats.splats, 1000u);
  ASSERT_LT(one.stats.top, one.stats.bottom);
  EXPECT_EQ(three.stats.top, one.stats.top);
  EXPECT_EQ(three.stats.bottom, one.stats.bottom);
  size_t differ = 0, drawn = 0;
  const size_t first = size_t(one.stats.top) * 320, last = size_t(one.stats.bottom) * 320;
  for (size_t i = first; i < last; ++i) {
    drawn += (one.rgba[i] >> 24) != 0;
    // Opaque posts: the nearest one wins whatever the thread that drew it.
    differ += one.rgba[i] != three.rgba[i];
    if (std::isfinite(one.depth[i])) {
      EXPECT_NEAR(one.depth[i], three.depth[i], 1e-3f);
    }
  }
  EXPECT_GT(drawn, 500u);
  EXPECT_LE(differ, drawn / 100) << "pixels whose colour depends on the thread split";
}

TEST(FrameWarp, ThePictureDepthIsTheDistanceAlongTheViewAxis) {
  // Looking north along y from (2, -10, 1.5): a post's layer at height h on tile (0, 0)
  // stands at view distance y + 10.
  const View view = viewFrom({2, -10, 1.5}, {2, 0, 1.5});
  TwoLdis ldis;
  TileDraw t;
  t.ldis[0] = {0, 0, 1.0f};
  t.ldiCount = 1;
  t.placement = {glm::vec2(0), 4.0f, {0, 0, 0, 0}};
  t.distance = 12;
  t.screenPixels = 100;
  const int w = 320, h = 240;
  std::vector<uint32_t> rgba(size_t(w) * h);
  std::vector<float> depth(size_t(w) * h);
  FrameWarper warper;
  const FrameWarpStats stats = warper.warp({&t, 1}, ldis, view, {}, {w, h, rgba, depth});
  ASSERT_GT(stats.splats, 0u);
  // Every drawn pixel's depth lies within the tile's y range, 10 to 14 m away.
  size_t drawn = 0;
  for (size_t i = size_t(stats.top) * w; i < size_t(stats.bottom) * w; ++i) {
    if ((rgba[i] >> 24) == 0) {
      EXPECT_TRUE(std::isinf(depth[i]));
      continue;
    }
    ++drawn;
    EXPECT_GE(depth[i], 10.0f - 0.05f);
    EXPECT_LE(depth[i], 14.0f + 0.05f);
  }
  EXPECT_GT(drawn, 20u);
}

}  // namespace
}  // namespace terralod::veg
