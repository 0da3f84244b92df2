#include "terralod/runtime/horizon_culling.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <random>
#include <span>

#include "test_tree.h"

namespace terralod {
namespace {

// Rolling mountains over 8 km: every chunk draws exactly this surface (within its box, no
// cracks), which is what the culling assumes of the drawn terrain.
constexpr double kSpacing = 8.0;
constexpr uint32_t kCells = 1024;
double height(double x, double y) {
  return 300.0 * std::sin(x / 700.0) * std::cos(y / 900.0) + 150.0 * std::sin((x + y) / 350.0) +
         80.0 * std::sin(x / 130.0 + 2.0 * std::sin(y / 200.0)) + 400.0;
}
// A bound of |grad height|: 300 (1/700 + 1/900) + 150 sqrt(2) / 350 + 80 (1/130 + 2/200 * ...).
constexpr double kLipschitz = 3.0;

// Surface bounds per 16 m square (2 x 2 cells): min and max over samples every 2 m, boundaries
// included, widened by kLipschitz * 2 m (every point is within 2 m of a sample).
constexpr double kFine = 16.0, kStep = 2.0;
constexpr uint32_t kFineSquares = uint32_t(kCells * kSpacing / kFine);

struct Mountains {
  FullTree full{6, kCells};
  std::vector<float> fineMin, fineMax;  // kFineSquares^2, row by row
  ChunkTree tree;
  // Per node, a grid of floors as a kind's decode makes them (here from the surface bounds).
  std::vector<OccluderGrid> grids;

  Mountains() : tree(build(full, fineMin, fineMax)) {
    for (uint32_t i = 0; i < tree.nodes().size(); ++i) grids.push_back(grid(i));
  }

  static ChunkTree build(FullTree& f, std::vector<float>& fineMin, std::vector<float>& fineMax) {
    f.header.spacingX = f.header.spacingY = kSpacing;
    for (int l = 0; l < 6; ++l) f.header.levelError[size_t(l)] = 64.0 / double(1 << l);
    f.header.extentMax = {kCells * kSpacing, kCells * kSpacing, 1000.0};
    fineMin.resize(size_t(kFineSquares) * kFineSquares);
    fineMax.resize(fineMin.size());
    for (uint32_t j = 0; j < kFineSquares; ++j)
      for (uint32_t i = 0; i < kFineSquares; ++i) {
        double lo = 1e30, hi = -1e30;
        for (double x = i * kFine; x <= (i + 1) * kFine + 1e-9; x += kStep)
          for (double y = j * kFine; y <= (j + 1) * kFine + 1e-9; y += kStep) {
            lo = std::min(lo, height(x, y));
            hi = std::max(hi, height(x, y));
          }
        fineMin[size_t(j) * kFineSquares + i] = float(lo - kLipschitz * kStep);
        fineMax[size_t(j) * kFineSquares + i] = float(hi + kLipschitz * kStep);
      }
    // Leaves: their squares' bounds; parents: the union of their children (nodes are breadth
    // first: children after parents).
    for (size_t i = f.nodes.size(); i-- > 0;) {
      NodeRecord& n = f.nodes[i];
      n.maxSkirtDepth = 1.0f;
      if (n.childMask != 0) {
        n.minZ = 1e30f;
        n.maxZ = -1e30f;
        for (uint32_t c = n.firstChild; c < n.firstChild + 4; ++c) {
          n.minZ = std::min(n.minZ, f.nodes[c].minZ);
          n.maxZ = std::max(n.maxZ, f.nodes[c].maxZ);
        }
        continue;
      }
      const uint32_t side = uint32_t(f.header.chunkCells(n.level) * kSpacing / kFine);
      n.minZ = 1e30f;
      n.maxZ = -1e30f;
      for (uint32_t v = n.y * side; v < (n.y + 1) * side; ++v)
        for (uint32_t u = n.x * side; u < (n.x + 1) * side; ++u) {
          n.minZ = std::min(n.minZ, fineMin[size_t(v) * kFineSquares + u]);
          n.maxZ = std::max(n.maxZ, fineMax[size_t(v) * kFineSquares + u]);
        }
    }
    return ChunkTree(f.header, f.nodes);
  }

  // A node's occluder grid: 16 x 16 cells over its footprint (in grid cells from its corner),
  // each the least floor of the 16 m squares in it.
  OccluderGrid grid(uint32_t node) const {
    const ChunkNode& n = tree.node(node);
    const uint32_t cells = uint32_t(tree.chunkCells(n.level));
    OccluderGridBuilder builder({0, 0}, {cells, cells});
    const uint32_t x0 = uint32_t(n.box.min[0] / kFine), y0 = uint32_t(n.box.min[1] / kFine);
    const uint32_t per = uint32_t(kFine / kSpacing);  // grid cells a square spans
    for (uint32_t j = 0; j < cells / per; ++j)
      for (uint32_t i = 0; i < cells / per; ++i)
        builder.addTriangle({i * per, (i + 1) * per, i * per}, {j * per, j * per, (j + 1) * per},
                            fineMin[size_t(y0 + j) * kFineSquares + x0 + i]);
    return std::move(builder).finish();
  }
};

// Built once (a few seconds of sampling) for the tests that fly over it.
const Mountains& mountains() {
  static const Mountains m;
  return m;
}

// True when the segment from `eye` to `p` dips below the surface before reaching `stop` of the
// way (horizontally), found by sphere tracing with the Lipschitz bound (never steps over a dip).
bool hiddenBefore(const glm::dvec3& eye, const glm::dvec3& p, double stop) {
  const glm::dvec3 d = p - eye;
  const double horizontal = std::hypot(d.x, d.y);
  const double slope = std::fabs(d.z) / horizontal;
  for (double s = 0.0; s < stop;) {
    const glm::dvec3 q = eye + d * s;
    const double gap = q.z - height(q.x, q.y);
    if (gap < 0.0) return true;
    s += std::max(gap / (kLipschitz + slope), 0.01) / horizontal;
  }
  return false;
}

// The top of the finest chunk box over (x, y), as the automatic flight keeps its clearance.
double finestTop(const ChunkTree& tree, double x, double y) {
  uint32_t i = 0;
  for (bool deeper = true; deeper;) {
    deeper = false;
    const ChunkNode& n = tree.node(i);
    for (uint32_t c = n.firstChild; c < n.firstChild + n.childCount; ++c) {
      const Box& b = tree.node(c).box;
      if (x >= b.min[0] && x <= b.max[0] && y >= b.min[1] && y <= b.max[1]) {
        i = c;
        deeper = true;
        break;
      }
    }
  }
  return tree.node(i).box.max[2];
}

Camera randomLowCamera(const ChunkTree& tree, std::mt19937& rng, double clearanceMin,
                       double clearanceMax) {
  std::uniform_real_distribution<double> xy(1000.0, kCells * kSpacing - 1000.0);
  std::uniform_real_distribution<double> up(clearanceMin, clearanceMax),
      azimuth(0.0, 2 * std::numbers::pi), pitch(-0.5, 0.1);
  Camera c;
  c.eye = {xy(rng), xy(rng), 0.0};
  c.eye.z = finestTop(tree, c.eye.x, c.eye.y) + up(rng);
  const double a = azimuth(rng), p = pitch(rng);
  c.target = c.eye + glm::dvec3(std::cos(a) * std::cos(p), std::sin(a) * std::cos(p), std::sin(p));
  c.width = 640;
  c.height = 480;
  c.hfovDegrees = 60.0;
  return c;
}

// Flies 24 low cameras over the mountains and checks every culled chunk with rays; returns
// the share of the selected chunks culled.
double checkCullingWithRays(std::span<const OccluderGrid> grids) {
  const Mountains& m = mountains();
  std::mt19937 rng(19);
  HorizonCuller culler;
  SelectionOptions options;
  std::vector<SelectedChunk> selected, visible;
  uint64_t total = 0, culled = 0, checked = 0;
  int active = 0;
  for (int camera = 0; camera < 24; ++camera) {
    const View view = makeView(randomLowCamera(m.tree, rng, 5.0, 200.0)).value();
    selectChunks(m.tree, view, options, selected);
    const HorizonCullingStats stats = culler.cull(m.tree, view, selected, 0.05, visible, grids);
    active += stats.active ? 1 : 0;
    EXPECT_EQ(visible.size() + stats.culled, selected.size());
    total += selected.size();
    culled += stats.culled;
    std::vector<uint8_t> kept(m.tree.nodes().size(), 0);
    for (const SelectedChunk& s : visible) kept[s.node] = 1;
    for (const SelectedChunk& s : selected) {
      if (kept[s.node]) continue;
      const Box& b = m.tree.node(s.node).box;
      // Points over the chunk's footprint, edges included: each is hidden well before it.
      for (int i = 0; i <= 6; ++i)
        for (int j = 0; j <= 6; ++j) {
          const double x = b.min[0] + (b.max[0] - b.min[0]) * i / 6.0;
          const double y = b.min[1] + (b.max[1] - b.min[1]) * j / 6.0;
          const glm::dvec3 p{x, y, height(x, y)};
          EXPECT_TRUE(hiddenBefore(view.camera.eye, p, 0.9999))
              << "camera " << camera << " chunk " << s.node << " point " << x << "," << y;
          ++checked;
        }
    }
  }
  std::printf("%s: %d of 24 cameras active, %llu of %llu chunks culled, %llu points checked\n",
              grids.empty() ? "boxes" : "grids", active, (unsigned long long)culled,
              (unsigned long long)total, (unsigned long long)checked);
  EXPECT_GT(checked, 500u);
  // (Off where a chunk's box near the eye reaches within a few near planes of it.)
  EXPECT_GE(active, 20);
  return double(culled) / double(total);
}

TEST(HorizonCulling, NeverCullsAPointOfTheSurfaceThatARayReaches) {
  // Low over mountains some of what is selected is behind a ridge (about 30 % here, by this
  // test's rays); boxes of whole chunks (and of their descendants) find a small part of it.
  EXPECT_GT(checkCullingWithRays({}), 0.01);
}

TEST(HorizonCulling, WithOccluderGridsNeverCullsAPointThatARayReaches) {
  // Grids of floors under each chunk's surface find several times more (11 % here).
  EXPECT_GT(checkCullingWithRays(mountains().grids), 0.08);
}

TEST(HorizonCulling, OccluderGridFloorsLieUnderEveryTriangleTouchingTheirCell) {
  // Random triangles over a 100 x 60 footprint in 16 x 16 cells (the x cells 6.25 wide, the
  // y cells 3.75 tall), boundaries included.
  std::mt19937 rng(7);
  std::uniform_int_distribution<uint32_t> x(10, 110), y(20, 80);
  std::uniform_real_distribution<double> z(-100.0, 100.0);
  OccluderGridBuilder builder({10, 20}, {110, 80});
  struct Tri {
    std::array<uint32_t, 3> xs, ys;
    double lowest;
  };
  std::vector<Tri> tris;
  for (int t = 0; t < 200; ++t) {
    Tri tri{{x(rng), x(rng), x(rng)}, {y(rng), y(rng), y(rng)}, z(rng)};
    tri.xs[1] = std::min(tri.xs[0] + 3, 110u);  // some small ones
    builder.addTriangle(tri.xs, tri.ys, tri.lowest);
    tris.push_back(tri);
  }
  builder.addTriangle({10, 10, 10}, {20, 20, 20}, -500.0);  // a point on the corner
  const OccluderGrid grid = std::move(builder).finish();
  ASSERT_EQ(grid.cellsX, 16u);
  ASSERT_EQ(grid.cellsY, 16u);
  EXPECT_EQ(grid.floors[0], -500.0f);
  for (uint32_t j = 0; j < 16; ++j)
    for (uint32_t i = 0; i < 16; ++i) {
      double expected = std::numeric_limits<double>::infinity();
      for (const Tri& t : tris) {
        const auto [x0, x1] = std::minmax({t.xs[0], t.xs[1], t.xs[2]});
        const auto [y0, y1] = std::minmax({t.ys[0], t.ys[1], t.ys[2]});
        if (x0 <= grid.columnX(i + 1) && x1 >= grid.columnX(i) && y0 <= grid.rowY(j + 1) &&
            y1 >= grid.rowY(j))
          expected = std::min(expected, t.lowest);
      }
      if (i == 0 && j == 0) expected = -500.0;
      const float floor = grid.floors[size_t(j) * 16 + i];
      if (std::isinf(expected)) {
        EXPECT_EQ(floor, -std::numeric_limits<float>::infinity());
      } else {
        EXPECT_LE(double(floor), expected) << i << "," << j;
        EXPECT_GT(double(floor), expected - 1e-5) << i << "," << j;
      }
    }
  // A footprint narrower than 16 cells gets one grid cell per cell; an empty one no grid.
  EXPECT_EQ(OccluderGridBuilder({0, 0}, {4, 32}).finish().cellsX, 4u);
  EXPECT_TRUE(OccluderGridBuilder({0, 0}, {0, 32}).finish().empty());
}

TEST(HorizonCulling, CullsNothingWithTheEyeBelowTheTerrainOrOutsideTheData) {
  const Mountains& m = mountains();
  HorizonCuller culler;
  SelectionOptions options;
  std::vector<SelectedChunk> selected, visible;
  const glm::dvec2 p{3000.0, 5000.0};
  auto run = [&](glm::dvec3 eye, glm::dvec3 target) {
    const View view = viewFrom(eye, target, 640);
    selectChunks(m.tree, view, options, selected);
    const HorizonCullingStats stats = culler.cull(m.tree, view, selected, 0.05, visible);
    EXPECT_EQ(visible.size(), selected.size());
    return stats;
  };
  const double ground = height(p.x, p.y);
  const HorizonCullingStats below =
      run({p.x, p.y, ground - 1.0}, {p.x + 1000.0, p.y, ground - 100.0});
  EXPECT_FALSE(below.active);
  EXPECT_EQ(below.culled, 0u);
  EXPECT_FALSE(run({-50.0, p.y, 2000.0}, {4000.0, p.y, 0.0}).active) << "outside the data";
  EXPECT_FALSE(run({p.x, p.y, ground + 0.1}, {p.x + 1000.0, p.y, ground}).active)
      << "a chunk within a few near planes";
  const double top = finestTop(m.tree, p.x, p.y);
  EXPECT_TRUE(run({p.x, p.y, top + 1.0}, {p.x + 1000.0, p.y, ground}).active);
}

TEST(HorizonCulling, AWallHidesWhatIsBehindItAndNotWhatRisesAboveIt) {
  // Flat ground at 0 m, 1 m cells, leaves of 64 cells, and a 100 m high wall filling the
  // column of leaves x = 576..640. From 10 m up at x = 300 looking east, the ground behind the
  // wall is hidden, a 500 m tower behind it is not, nor anything in front.
  FullTree f(5, 1024);
  for (NodeRecord& n : f.nodes) {
    const double side = double(f.header.chunkCells(n.level));
    const double x0 = n.x * side;
    const bool wall = x0 < 640.0 && x0 + side > 576.0;
    n.minZ = wall && n.level == 4 ? 100.0f : 0.0f;
    n.maxZ = wall ? 100.0f : 0.0f;
    n.maxSkirtDepth = 1.0f;
  }
  const auto tower = std::find_if(f.nodes.begin(), f.nodes.end(), [&](const NodeRecord& n) {
    return n.level == 4 && n.x == 14 && n.y == 8;  // x 896..960, y 512..576
  });
  tower->maxZ = 500.0f;
  const ChunkTree tree(f.header, f.nodes);
  const View view = viewFrom({300.0, 544.0, 10.0}, {1000.0, 544.0, 0.0}, 640);
  std::vector<SelectedChunk> selected, visible;
  SelectionOptions options;
  options.tau = 0.01;  // every chunk at the finest level
  selectChunks(tree, view, options, selected);
  HorizonCuller culler;
  const HorizonCullingStats stats = culler.cull(tree, view, selected, 0.05, visible);
  ASSERT_TRUE(stats.active);
  EXPECT_EQ(stats.culled, selected.size() - visible.size());
  std::vector<uint8_t> kept(tree.nodes().size(), 0);
  for (const SelectedChunk& s : visible) kept[s.node] = 1;
  int hiddenBehindWall = 0;
  for (const SelectedChunk& s : selected) {
    const ChunkNode& n = tree.node(s.node);
    if (s.node == uint32_t(tower - f.nodes.begin())) {
      EXPECT_TRUE(kept[s.node]) << "the tower rises above the wall";
    } else if (n.box.min[0] >= 704.0 && n.box.min[1] >= 448.0 && n.box.max[1] <= 640.0) {
      // Ground behind the wall (past its far corners), around the line of sight.
      EXPECT_FALSE(kept[s.node]) << "chunk at " << n.box.min[0] << "," << n.box.min[1];
      ++hiddenBehindWall;
    } else if (n.box.max[0] <= 576.0) {
      EXPECT_TRUE(kept[s.node]) << "in front of the wall";
    }
  }
  EXPECT_EQ(hiddenBehindWall, 3 * 5 - 1);  // 3 rows of 5 leaves, but the tower
}

}  // namespace
}  // namespace terralod
