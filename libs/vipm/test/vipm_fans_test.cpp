// Fan stitching's border cases on a hand-made chunk (vipm_fans.h); the built tileset's cuts
// are checked whole in libs/build/test/vipm_stitch_test.cpp.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <set>
#include <tuple>

#include "terralod/vipm/vipm_fans.h"

namespace terralod {
namespace {

// A 3 x 3 chunk without collapses, cells split by the diagonal from (x + 1, y) to (x, y + 1):
// its south-west triangle has edges on two sides.
ProgressiveMesh smallMesh() {
  ProgressiveMesh m;
  m.width = m.height = 3;
  for (uint16_t p = 0; p < 9; ++p) m.points.push_back(p);
  for (uint16_t y = 0; y < 2; ++y)
    for (uint16_t x = 0; x < 2; ++x) {
      const uint16_t a = uint16_t(y * 3 + x), b = uint16_t(a + 1), c = uint16_t(a + 3),
                     d = uint16_t(a + 4);
      m.triangles.push_back({a, b, c});
      m.triangles.push_back({b, d, c});
    }
  return m;
}

struct Chunk {
  ProgressiveMesh mesh = smallMesh();
  std::vector<std::array<float, 3>> drawn;
  std::vector<std::array<uint8_t, kMaxMaterials>> weights;
  std::vector<uint8_t> materials;
  std::vector<uint16_t> living;
  VipmStitcher stitcher;

  explicit Chunk(StitchChunk where) : stitcher(mesh, where) {
    for (uint16_t p : mesh.points)
      drawn.push_back({float(p % 3), float(p / 3), float(10 * (p % 3) + p / 3)});
    weights.assign(9, {});
    materials.assign(9, 0);
    for (const auto& t : mesh.triangles) living.insert(living.end(), t.begin(), t.end());
  }
  void add(StitchTable& table) const { stitcher.addPoints(table, 9, drawn, weights, materials); }
  StitchFans fans(const StitchTable& table) const {
    StitchFans f;
    stitcher.fan(table, living, drawn, f);
    return f;
  }
  // The points of the fans' edges on the line x = `x` (or y = `y`), as (along, z), sorted.
  std::set<std::pair<double, double>> edgePoints(const StitchFans& f, int axis, double at) const {
    std::set<std::pair<double, double>> out;
    for (const auto& t : f.triangles)
      for (int e = 0; e < 3; ++e) {
        std::array<std::array<float, 3>, 2> ends;
        for (int k = 0; k < 2; ++k) {
          const uint32_t v = t[size_t((e + k) % 3)];
          ends[size_t(k)] = v < 9 ? drawn[v] : f.positions[v - 9];
        }
        if (ends[0][size_t(axis)] == at && ends[1][size_t(axis)] == at)
          for (const auto& p : ends) out.insert({p[size_t(1 - axis)], p[2]});
      }
    return out;
  }
};

TEST(VipmFans, APointBesideAVertexAtAnotherHeightJoinsThePolylineAboveIt) {
  // A neighbour's vertex sliding along the shared side stands where this chunk has a vertex,
  // at another height: both polylines hold both, one above the other.
  Chunk a({0, 0, 0.0, 3, 3, 0});
  StitchTable table;
  a.add(table);
  StitchPoint sliding;
  sliding.along = 1.0;
  sliding.z = double(a.drawn[5][2]) + 5.0;  // above vertex (2, 1)
  table.add({0, 2}, sliding);
  table.finish();
  const StitchFans f = a.fans(table);
  ASSERT_EQ(f.positions.size(), 1u);
  EXPECT_EQ(f.replaced.size(), 1u);
  const std::set<std::pair<double, double>> expected{
      {0.0, 20.0}, {1.0, 21.0}, {1.0, 26.0}, {2.0, 22.0}};
  const auto got = a.edgePoints(f, 0, 2.0);
  // Only the fanned triangle's edges are in `f`: the piece above vertex (2, 1) and up.
  for (const auto& p : got) EXPECT_TRUE(expected.count(p)) << p.first << " " << p.second;
  EXPECT_TRUE(got.count({1.0, 26.0}));
  EXPECT_TRUE(got.count({1.0, 21.0}));
}

TEST(VipmFans, ACornerTriangleIsFannedAlongBothSides) {
  Chunk a({0, 0, 0.0, 3, 3, 0});
  StitchTable table;
  a.add(table);
  StitchPoint south, west;
  south.along = 0.5;  // on y = 0 at x = 0.5
  south.z = 3.0;
  west.along = 0.5;  // on x = 0 at y = 0.5
  west.z = 4.0;
  table.add({1, 0}, south);
  table.add({0, 0}, west);
  table.finish();
  const StitchFans f = a.fans(table);
  EXPECT_EQ(f.replaced, std::vector<uint32_t>{0});
  EXPECT_EQ(f.triangles.size(), 3u);  // one triangle, two points inserted
  EXPECT_TRUE(a.edgePoints(f, 1, 0.0).count({0.5, 3.0}));
  EXPECT_TRUE(a.edgePoints(f, 0, 0.0).count({0.5, 4.0}));
  // The fans cover the triangle they replace, counter-clockwise.
  double area = 0.0;
  for (const auto& t : f.triangles) {
    std::array<std::array<float, 3>, 3> p;
    for (int k = 0; k < 3; ++k)
      p[size_t(k)] = t[size_t(k)] < 9 ? a.drawn[t[size_t(k)]] : f.positions[t[size_t(k)] - 9];
    const double s = 0.5 * ((p[1][0] - p[0][0]) * (p[2][1] - p[0][1]) -
                            (p[1][1] - p[0][1]) * (p[2][0] - p[0][0]));
    EXPECT_GT(s, 0.0);
    area += s;
  }
  EXPECT_DOUBLE_EQ(area, 0.5);
}

TEST(VipmFans, NeighboursInsertEachOthersPointsInTheirOwnFrames) {
  // Two chunks side by side, their own corners and zBases: each inserts the other's points
  // where that one draws them.
  Chunk a({128, 64, 1000.0, 3, 3, 0}), b({130, 64, 1040.0, 3, 3, 0});
  // b's west side meets a's east side (heights 1020, 1021, 1022) but for b's (0, 1), a
  // quarter metre higher (as if sliding there).
  for (int y = 0; y < 3; ++y) b.drawn[size_t(3 * y)][2] = float(-20 + y);
  b.drawn[3][2] += 0.25f;
  StitchTable table;
  a.add(table);
  b.add(table);
  table.finish();
  const StitchFans fa = a.fans(table), fb = b.fans(table);
  ASSERT_EQ(fa.positions.size(), 1u);
  ASSERT_EQ(fb.positions.size(), 1u);
  EXPECT_EQ(fa.positions[0], (std::array<float, 3>{2.0f, 1.0f, 21.25f}));
  EXPECT_EQ(fb.positions[0], (std::array<float, 3>{0.0f, 1.0f, -19.0f}));
}

TEST(VipmFans, NothingChangesWithoutOtherPoints) {
  Chunk a({0, 0, 0.0, 3, 3, 0});
  StitchTable table;
  a.add(table);
  table.finish();
  const StitchFans f = a.fans(table);
  EXPECT_TRUE(f.replaced.empty());
  EXPECT_TRUE(f.triangles.empty());
  EXPECT_LE(table.pointCount(), 12u);
}

TEST(VipmFans, TheSignatureFollowsWhatTheFansAreMadeOf) {
  // Equal signatures promise equal fans: the chunk's level, and the points on its lines.
  Chunk a({0, 0, 0.0, 3, 3, 0});
  auto signatureWith = [&](double z, double along, int64_t line) {
    StitchTable table;
    a.add(table);
    StitchPoint p;
    p.along = along;
    p.z = z;
    table.add({0, line}, p);
    table.finish();
    return a.stitcher.signature(table, 0);
  };
  const uint64_t base = signatureWith(5.0, 1.5, 2);
  EXPECT_EQ(signatureWith(5.0, 1.5, 2), base);
  EXPECT_NE(signatureWith(5.25, 1.5, 2), base);  // a neighbour's point moved
  EXPECT_NE(signatureWith(5.0, 1.75, 2), base);
  EXPECT_EQ(signatureWith(5.0, 1.5, 7), signatureWith(6.0, 1.5, 7));  // not on its lines
  EXPECT_EQ(signatureWith(5.0, 7.0, 2), signatureWith(6.0, 7.0, 2));  // beyond its span
  StitchTable table;
  a.add(table);
  table.finish();
  EXPECT_NE(a.stitcher.signature(table, 0), a.stitcher.signature(table, 1));
}

TEST(VipmFans, RoundedPointsOnLinesMoveIntoTheLargestFrameExactly) {
  // A leaf at (8192, 4096) of a tileset whose top node has 8192 cells; a point on its south
  // side (y = 0) moves into the frames of its neighbours up to the top node's.
  for (uint32_t largest : {128u, 8192u, 32768u}) {
    const StitchChunk leaf{8192, 4096, 1000.0, 65, 65, 0, largest};
    std::array<float, 3> p{37.123456f, 0.0f, 812.34567f};
    roundStitchPoint(p, leaf);
    for (int64_t corner :
         {int64_t(8192 - 64), int64_t(8192 + 64), int64_t(8192 - 128), int64_t(0)}) {
      const double local = double(leaf.cornerX) + double(p[0]) - double(corner);
      if (local > double(largest)) continue;
      EXPECT_EQ(double(float(local)), local) << largest << " " << corner;
    }
    const double z = double(p[2]) + 1000.0 - 1024.0;
    EXPECT_EQ(double(float(z)), z);
    EXPECT_NEAR(p[0], 37.123456f, stitchQuantum(largest));
  }
  EXPECT_EQ(stitchQuantum(128), std::ldexp(1.0, -16));
  EXPECT_EQ(stitchQuantum(129), std::ldexp(1.0, -15));
  EXPECT_EQ(stitchQuantum(8192), std::ldexp(1.0, -10));
  // Off the lines a vertex is left where it is (rounding could move it onto one).
  const StitchChunk root{0, 0, 0.0, 129, 129, 64, 8192};
  std::array<float, 3> inner{63.9999f, 12.3456789f, 5.4321f};
  const auto before = inner;
  roundStitchPoint(inner, root);
  EXPECT_EQ(inner, before);
  std::array<float, 3> seam{64.0f, 12.3456789f, 5.4321f};  // on the root's inner seam
  roundStitchPoint(seam, root);
  EXPECT_NE(seam[1], before[1]);
  EXPECT_EQ(seam[0], 64.0f);
}

// A corner triangle is cut on its finer line first, as the joins above the roots close it: a
// root's inner seam (64) before the side between roots (128), that before a 256-cell node's
// side; x = c before y = c on lines alike; the map's edge last.
TEST(StitchLineOrder, FinerLinesFirstThenXBeforeY) {
  const auto order = [](uint8_t axis, int64_t at) { return stitchLineOrder({axis, at}); };
  EXPECT_LT(order(0, 64), order(0, 128));
  EXPECT_LT(order(1, 192), order(0, 256));  // 192 = 3 x 64: a 64-cell line
  EXPECT_LT(order(0, 128), order(1, 128));
  EXPECT_LT(order(1, 64), order(0, 128));
  EXPECT_EQ(order(0, 64), order(0, 192));
  EXPECT_LT(order(0, 1 << 20), order(0, 0));
}

}  // namespace
}  // namespace terralod
