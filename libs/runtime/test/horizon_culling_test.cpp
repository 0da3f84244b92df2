#include "terralod/runtime/horizon_culling.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <random>

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

struct Mountains {
  FullTree full{6, kCells};
  ChunkTree tree;

  Mountains() : tree(build(full)) {}

  static ChunkTree build(FullTree& f) {
    f.header.spacingX = f.header.spacingY = kSpacing;
    for (int l = 0; l < 6; ++l) f.header.levelError[size_t(l)] = 64.0 / double(1 << l);
    f.header.extentMax = {kCells * kSpacing, kCells * kSpacing, 1000.0};
    // Leaves sampled every 2 m (a point is within kLipschitz * 2 m of a sample), parents
    // the union of their children (nodes are breadth first: children after parents).
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
      const double side = double(f.header.chunkCells(n.level)) * kSpacing, step = 2.0;
      double lo = 1e30, hi = -1e30;
      for (double x = n.x * side; x <= (n.x + 1) * side + 1e-9; x += step)
        for (double y = n.y * side; y <= (n.y + 1) * side + 1e-9; y += step) {
          lo = std::min(lo, height(x, y));
          hi = std::max(hi, height(x, y));
        }
      n.minZ = float(lo - kLipschitz * step);
      n.maxZ = float(hi + kLipschitz * step);
    }
    return ChunkTree(f.header, f.nodes);
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

TEST(HorizonCulling, NeverCullsAPointOfTheSurfaceThatARayReaches) {
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
    const HorizonCullingStats stats = culler.cull(m.tree, view, selected, 0.05, visible);
    active += stats.active ? 1 : 0;
    ASSERT_EQ(visible.size() + stats.culled, selected.size());
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
          ASSERT_TRUE(hiddenBefore(view.camera.eye, p, 0.9999))
              << "camera " << camera << " chunk " << s.node << " point " << x << "," << y;
          ++checked;
        }
    }
  }
  // Low over mountains some of what is selected is behind a ridge (about 30 % here, by this
  // test's rays; boxes of whole chunks find a small part of it).
  EXPECT_GT(double(culled), 0.01 * double(total)) << culled << " of " << total;
  std::printf("%d of 24 cameras active, %llu of %llu chunks culled, %llu points checked\n", active,
              (unsigned long long)culled, (unsigned long long)total, (unsigned long long)checked);
  EXPECT_GT(checked, 500u);
  // (Off where a chunk's box near the eye reaches within a few near planes of it.)
  EXPECT_GE(active, 20);
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
