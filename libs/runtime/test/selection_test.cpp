#include "terralod/runtime/selection.h"

#include "test_tree.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

namespace terralod {
namespace {

TEST(View, RejectsImpossibleCameras) {
  Camera c;
  c.eye = c.target = {1, 2, 3};
  EXPECT_FALSE(makeView(c).ok());
  c.target = {1, 2, 4};
  c.eye.x = std::nan("");
  EXPECT_FALSE(makeView(c).ok());
  c.eye = {0, 0, 0};
  c.width = 0;
  EXPECT_FALSE(makeView(c).ok());
  c.width = 100;
  c.hfovDegrees = 180;
  EXPECT_FALSE(makeView(c).ok());
  c.hfovDegrees = 60;
  EXPECT_TRUE(makeView(c).ok()) << "straight up is a legal camera";
}

TEST(View, FrustumKeepsWhatIsInFrontAndCullsWhatIsBehind) {
  const View v = viewFrom({0, 0, 10}, {0, 100, 10});
  EXPECT_DOUBLE_EQ(v.pixelsPerRadian, 500.0);
  EXPECT_TRUE(boxInFrustum(v, Box{{-1, 50, 9}, {1, 51, 11}}));
  EXPECT_FALSE(boxInFrustum(v, Box{{-1, -51, 9}, {1, -50, 11}})) << "behind the eye";
  EXPECT_FALSE(boxInFrustum(v, Box{{200, 50, 9}, {201, 51, 11}})) << "right of a 90 degree view";
  EXPECT_TRUE(boxInFrustum(v, Box{{-5, -5, 0}, {5, 5, 20}})) << "around the eye";
  EXPECT_DOUBLE_EQ(distanceToBox({0, 0, 0}, Box{{3, 4, -1}, {5, 6, 1}}), 5.0);
}

TEST(View, ABoxWithinTheFrustumHasEveryPointInIt) {
  const View v = viewFrom({0, 0, 10}, {0, 100, 10});
  EXPECT_TRUE(boxWithinFrustum(v, Box{{-1, 50, 9}, {1, 51, 11}}));
  EXPECT_FALSE(boxWithinFrustum(v, Box{{-5, -5, 0}, {5, 5, 20}})) << "around the eye";
  EXPECT_FALSE(boxWithinFrustum(v, Box{{-1, -51, 9}, {1, -50, 11}})) << "behind the eye";
  // Whenever it says within, so does every plane at random points of the box.
  std::mt19937 random(7);
  std::uniform_real_distribution<double> at(-300.0, 300.0), size(0.0, 80.0);
  int within = 0;
  for (int k = 0; k < 2000; ++k) {
    const glm::dvec3 lo{at(random), std::fabs(at(random)), at(random) / 10.0};
    const glm::dvec3 hi = lo + glm::dvec3(size(random), size(random), size(random));
    const Box b{{lo.x, lo.y, lo.z}, {hi.x, hi.y, hi.z}};
    if (!boxWithinFrustum(v, b)) continue;
    ++within;
    EXPECT_TRUE(boxInFrustum(v, b));
    for (int p = 0; p < 8; ++p) {
      const glm::dvec3 q{p & 1 ? hi.x : lo.x, p & 2 ? hi.y : lo.y, p & 4 ? hi.z : lo.z};
      for (const glm::dvec4& plane : v.planes)
        EXPECT_GE(glm::dot(glm::dvec3(plane), q) + plane.w, 0.0);
    }
  }
  EXPECT_GT(within, 10);
}

TEST(Selection, SplitsExactlyWhereRhoPassesTau) {
  const FullTree f(3);
  const ChunkTree tree = f.tree();
  // Eye due south of the root's box at height 50, looking north: D is the horizontal gap.
  // ρ = δ(0) K / D = 16 * 500 / D; with τ = 2 the root splits below D = 4000 m.
  SelectionOptions o;
  o.tau = 2.0;
  std::vector<SelectedChunk> out;
  auto at = [&](double gap) {
    const View v = viewFrom({512, -gap, 50}, {512, 512, 50});
    return selectChunks(tree, v, o, out);
  };
  EXPECT_EQ(at(4000.5).selected, 1u);
  EXPECT_EQ(out[0].node, 0u);
  const SelectionStats split = at(3999.5);
  EXPECT_GT(split.selected, 1u);
  EXPECT_EQ(split.deepestLevel, 1);
}

// Every split seen while the eye walks in small steps: the child's t when it appeared and its
// parent's t the frame before. `viewAt(gap)` is the camera for each gap from `from` down to
// `to`, shrinking 0.1 % a step.
struct Split {
  uint32_t child;
  float childMorph, parentMorphBefore;
};
template <typename ViewAt>
std::vector<Split> splitsAlong(const ChunkTree& tree, size_t nodes, double from, double to,
                               ViewAt viewAt) {
  SelectionOptions o;
  o.tau = 2.0;
  std::vector<SelectedChunk> out;
  std::vector<Split> splits;
  std::vector<float> previous(nodes, -1.0f);
  for (double gap = from; gap > to; gap *= 0.999) {
    selectChunks(tree, viewAt(gap), o, out);
    std::vector<float> now(nodes, -1.0f);
    for (const SelectedChunk& c : out) now[c.node] = c.morph;
    for (const SelectedChunk& c : out) {
      const uint32_t parent = tree.node(c.node).parent;
      if (previous[c.node] < 0 && parent != kNoNode && previous[parent] >= 0)
        splits.push_back({c.node, c.morph, previous[parent]});
    }
    previous = now;
  }
  return splits;
}

TEST(Selection, ChildrenStartAsTheirParentAndSplitAtZeroMorph) {
  const FullTree f(4);
  const ChunkTree tree = f.tree();
  // Walk the eye towards the terrain in small steps; at every frame where a chunk appears that
  // was not there before, it must start at t = 1 (its parent's shape); a chunk that is about
  // to split must be at t = 0 the frame before.
  const auto splits = splitsAlong(tree, f.nodes.size(), 5000, 10, [](double gap) {
    return viewFrom({300, -gap, 60}, {300, 512, 40});
  });
  for (const Split& s : splits) {
    EXPECT_GT(s.childMorph, 0.995f) << "chunk " << s.child << " appeared at t=" << s.childMorph;
    EXPECT_LT(s.parentMorphBefore, 0.01f)
        << "chunk " << s.child << "'s parent split at t=" << s.parentMorphBefore;
  }
  EXPECT_GT(splits.size(), 10u);
}

// Finer levels rise above coarser ones (a child's surface may: it refines its parent's). The
// tree nests the boxes, so a child is never nearer the eye than its parent and still appears at
// t = 1 when the eye comes straight down onto the peaks. (With each node's own box, children
// appeared at t = 0.94 here: a pop of 6 % of their morph deltas.)
TEST(Selection, ChildrenRisingAboveTheirParentStillStartAsTheirParent) {
  FullTree f(4);
  for (NodeRecord& n : f.nodes) n.maxZ = 100.0f + 30.0f * float(n.level);
  const ChunkTree tree = f.tree();
  for (size_t i = 1; i < f.nodes.size(); ++i) {
    const Box &child = tree.node(uint32_t(i)).box, &parent = tree.node(f.nodes[i].parent).box;
    for (int k = 0; k < 3; ++k) {
      EXPECT_GE(child.min[k], parent.min[k]);
      EXPECT_LE(child.max[k], parent.max[k]);
    }
  }
  const auto splits = splitsAlong(tree, f.nodes.size(), 3000, 2, [](double gap) {
    return viewFrom({300, 300, 190 + gap}, {300, 310, 0});
  });
  for (const Split& s : splits)
    EXPECT_GT(s.childMorph, 0.995f) << "chunk " << s.child << " appeared at t=" << s.childMorph;
  EXPECT_GT(splits.size(), 3u);
}

TEST(Selection, MorphRunsOverTheAllowedErrorBetweenLevelsThatDoNotHalve) {
  // A VIPM-like tree: the root's error is 12 times the leaves'. A leaf's t goes from 0 where
  // τ·D/K is its own error to 1 where it is the root's, so t = 1 still means "the parent's
  // error" (and a leaf appears at t = 1 when the root splits).
  FullTree f(2);
  f.header.levelError[0] = 24.0;
  f.header.levelError[1] = 2.0;
  const ChunkTree tree = f.tree();
  SelectionOptions o;
  o.tau = 2.0;
  std::vector<SelectedChunk> out;
  int checked = 0, appeared = 0;
  bool rootDrawn = false;
  for (double gap = 20000; gap > 1; gap *= 0.999) {
    const View v = viewFrom({300, -gap, 60}, {300, 512, 40});
    selectChunks(tree, v, o, out);
    for (const SelectedChunk& c : out) {
      const ChunkNode& n = tree.node(c.node);
      if (n.level == 0) continue;
      const double allowed = o.tau * distanceToBox(v.camera.eye, n.box) / v.pixelsPerRadian;
      const double expect = std::clamp((allowed - 2.0) / (24.0 - 2.0), 0.0, 1.0);
      EXPECT_NEAR(c.morph, expect, 1e-5) << gap;
      ++checked;
      if (rootDrawn) {
        ++appeared;
        EXPECT_GT(c.morph, 0.995f);
      }
    }
    rootDrawn = out.size() == 1 && out[0].node == 0;
  }
  EXPECT_GT(checked, 100);
  EXPECT_EQ(appeared, 4);
}

TEST(Selection, MorphedErrorNeverExceedsTau) {
  // For any camera: every drawn chunk that did not want to split has (1 + t) ρ <= τ.
  const FullTree f(5);
  const ChunkTree tree = f.tree();
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> xy(-500, 1500), z(1, 2000);
  std::vector<SelectedChunk> out;
  for (int k = 0; k < 300; ++k) {
    SelectionOptions o;
    o.tau = 1.0 + k % 4;
    const View v = viewFrom({xy(rng), xy(rng), z(rng)}, {xy(rng), xy(rng), 0.0});
    const SelectionStats s = selectChunks(tree, v, o, out);
    EXPECT_EQ(s.coarserThanWanted, 0u);
    for (const SelectedChunk& c : out) {
      const ChunkNode& n = tree.node(c.node);
      const double rho =
          screenSpaceError(v, tree.levelError(n.level), distanceToBox(v.camera.eye, n.box));
      if (n.childCount == 0 && rho > o.tau) continue;  // finest data: nothing better to draw
      EXPECT_LE((1.0 + c.morph) * rho, o.tau * (1 + 1e-6)) << "node " << c.node;
    }
  }
}

TEST(Selection, CullsWhatIsOutOfViewAndDrawsNothingLookingAway) {
  const FullTree f(3);
  const ChunkTree tree = f.tree();
  std::vector<SelectedChunk> out;
  const SelectionStats away =
      selectChunks(tree, viewFrom({512, -100, 50}, {512, -1000, 50}), SelectionOptions{}, out);
  EXPECT_EQ(away.selected, 0u);
  EXPECT_EQ(away.culled, 1u);
  // Close to the ground in a corner looking out along the south edge: much is culled.
  const SelectionStats corner =
      selectChunks(tree, viewFrom({10, 10, 5}, {1000, 10, 5}), SelectionOptions{}, out);
  EXPECT_GT(corner.culled, 0u);
  EXPECT_GT(corner.selected, 0u);
}

TEST(Selection, DrawsTheParentWhileChildrenAreMissing) {
  const FullTree f(3);
  const ChunkTree tree = f.tree();
  std::vector<uint8_t> drawable(f.nodes.size(), 1);
  drawable[3] = 0;  // one child of the root is not loaded
  SelectionOptions o;
  o.drawable = drawable;
  std::vector<SelectedChunk> out;
  const SelectionStats s = selectChunks(tree, viewFrom({512, -100, 50}, {512, 512, 0}), o, out);
  ASSERT_EQ(s.selected, 1u);
  EXPECT_EQ(out[0].node, 0u);
  EXPECT_EQ(out[0].morph, 0.0f);
  EXPECT_EQ(s.coarserThanWanted, 1u);
  drawable[0] = 0;
  EXPECT_EQ(selectChunks(tree, viewFrom({512, -100, 50}, {512, 512, 0}), o, out).undrawableRoots,
            1u);
}

TEST(Selection, NoMorphMeansZeroAndNoAllocationAfterReserve) {
  const FullTree f(5);
  const ChunkTree tree = f.tree();
  std::vector<SelectedChunk> out;
  out.reserve(f.nodes.size());
  const SelectedChunk* storage = out.data();
  SelectionOptions o;
  o.morph = false;
  for (int k = 0; k < 50; ++k) {
    selectChunks(tree, viewFrom({512, -50.0 * k, 30}, {512, 512, 0}), o, out);
    for (const SelectedChunk& c : out) ASSERT_EQ(c.morph, 0.0f);
  }
  EXPECT_EQ(out.data(), storage);
}

}  // namespace
}  // namespace terralod
