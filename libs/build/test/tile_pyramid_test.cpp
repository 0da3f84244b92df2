// How a staged build splits the texture pyramid above the blocks: each pass-2 job builds the
// nodes whose blocks are all its own, and the coarse job the ancestors of what the jobs leave.
// Every node must be built exactly once, whatever the number of jobs and the shape of the tree.

#include "terralod/build/tile_pyramid.h"

#include <gtest/gtest.h>

#include "terralod/build/chunk_pass.h"

namespace terralod {
namespace {

struct Split {
  int32_t columns, rows, leaf, block;
};

class PyramidSplit : public ::testing::TestWithParam<Split> {};

TEST_P(PyramidSplit, BuildsEveryNodeAboveTheBlocksOnce) {
  const Split c = GetParam();
  const TreeLayout layout = makeTreeLayout(c.columns, c.rows, c.leaf).value();
  const std::vector<NodeRecord> nodes = enumerateNodes(layout);
  const int32_t blockLevel = blockLevelOf(layout, c.block);
  const std::vector<uint32_t> blocks = blockNodesOf(nodes, blockLevel);
  ASSERT_GT(blocks.size(), 8u);
  for (size_t jobs : {size_t(1), size_t(3), size_t(4), size_t(7), blocks.size()}) {
    SCOPED_TRACE("jobs " + std::to_string(jobs));
    std::vector<int> built(nodes.size(), 0);
    std::vector<uint32_t> frontier;
    for (size_t j = 0; j < jobs; ++j) {
      const std::vector<uint32_t> mine(blocks.begin() + ptrdiff_t(blocks.size() * j / jobs),
                                       blocks.begin() + ptrdiff_t(blocks.size() * (j + 1) / jobs));
      const std::vector<uint8_t> builds = TilePyramid::buildableFrom(nodes, blockLevel, mine);
      for (size_t i = 0; i < nodes.size(); ++i) built[i] += builds[i];
      for (uint32_t f : TilePyramid::frontierOf(nodes, builds, mine)) frontier.push_back(f);
    }
    const std::vector<uint8_t> rest = TilePyramid::ancestorsOf(nodes, frontier);
    for (size_t i = 0; i < nodes.size(); ++i) {
      const int times = built[i] + rest[i];
      EXPECT_EQ(times, nodes[i].level < blockLevel ? 1 : 0)
          << "node " << i << " level " << int(nodes[i].level);
    }
    // What the coarse job is given are the children of what it builds, or roots.
    for (uint32_t f : frontier) {
      const uint32_t p = nodes[f].parent;
      EXPECT_TRUE(p == kNoNode ? nodes[f].level == 0 : rest[p] == 1) << "frontier node " << f;
    }
    if (jobs == 1) {
      for (uint32_t f : frontier) EXPECT_EQ(nodes[f].level, 0);
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Shapes, PyramidSplit,
                         ::testing::Values(Split{1024, 1024, 32, 64},  // one full root
                                           Split{700, 450, 32, 64},    // partial trees
                                           Split{2048, 640, 64, 128}   // several roots
                                           ));

}  // namespace
}  // namespace terralod
