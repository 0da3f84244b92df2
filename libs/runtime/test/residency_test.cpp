// The residency state machine, driven by hand with an inline task runner: deterministic
// counters for requests, priorities, cancellation, failures and retries, the budget and
// least-recently-used eviction, and selection drawing only what is resident.

#include "terralod/runtime/residency.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <set>
#include <thread>

#include "terralod/runtime/selection.h"
#include "test_tree.h"

namespace terralod {
namespace {

struct FakePayload : ChunkPayload {
  uint32_t node = 0;
};

class ResidencyTest : public ::testing::Test {
 protected:
  static constexpr uint64_t kChunkBytes = 1000;

  ResidencyTest() : mFull(4), mTree(mFull.tree()) {}

  std::unique_ptr<Residency> make(ResidencyOptions options) {
    return std::make_unique<Residency>(
        mTree,
        [this](uint32_t node) -> Result<LoadedChunk> {
          ++mLoadCalls;
          if (mFailing.count(node)) return Error{"chunk " + std::to_string(node) + " is broken"};
          auto p = std::make_unique<FakePayload>();
          p->node = node;
          return LoadedChunk{std::move(p), kChunkBytes, kChunkBytes, {}};
        },
        mRunner, options, [this](const std::string& line) { mLog.push_back(line); });
  }

  // Roots resident, as a scene starts.
  void loadRoot(Residency& r) {
    ASSERT_TRUE(r.loadNow(0).ok());
    r.markLoadedNow(0, kChunkBytes);
  }

  // One frame's tail: uploads everything ready.
  void uploadAll(Residency& r) {
    for (ReadyChunk& c : r.collect()) r.markResident(c, kChunkBytes);
  }

  // The root's children 1..last loaded and uploaded (nearest first).
  void loadChildren(Residency& r, uint32_t last) {
    for (uint32_t c = 1; c <= last; ++c) r.request(c, float(c));
    r.dispatch();
    mRunner.runAll();
    uploadAll(r);
  }

  FullTree mFull;
  ChunkTree mTree;
  InlineRunner mRunner;
  std::set<uint32_t> mFailing;
  std::atomic<int> mLoadCalls{0};
  std::vector<std::string> mLog;
};

TEST_F(ResidencyTest, RequestsLoadByPriorityWithinTheInFlightLimit) {
  ResidencyOptions o;
  o.maxInFlight = 2;
  auto r = make(o);
  loadRoot(*r);
  EXPECT_EQ(r->drawable()[0], 1);
  r->request(1, 3.0f);
  r->request(2, 1.0f);
  r->request(3, 2.0f);
  r->request(4, 4.0f);
  r->dispatch();
  EXPECT_EQ(r->inFlight(), 2u);
  EXPECT_EQ(r->state(2), ChunkState::kLoading);
  EXPECT_EQ(r->state(3), ChunkState::kLoading);
  EXPECT_EQ(r->state(1), ChunkState::kQueued);
  EXPECT_EQ(mRunner.runAll(), 2u);
  auto ready = r->collect();
  ASSERT_EQ(ready.size(), 2u);
  EXPECT_EQ(ready[0].node, 2u) << "most wanted first";
  EXPECT_EQ(ready[1].node, 3u);
  for (ReadyChunk& c : ready) r->markResident(c, kChunkBytes);
  EXPECT_EQ(r->drawable()[2], 1);
  EXPECT_EQ(r->drawable()[1], 0);
  EXPECT_EQ(r->counters().loads, 3u);  // the root and two children
  EXPECT_EQ(r->counters().residentBytes, 3 * kChunkBytes);
}

TEST_F(ResidencyTest, AReplacedNodeIsPendingOnlyWhileItsOldChunkIsHeld) {
  auto r = make({});
  loadRoot(*r);
  loadChildren(*r, 1);
  r->invalidate(1);  // resident: decoded again, drawn until the refresh lands
  r->invalidate(2);  // absent: simply loads the new bytes when wanted
  EXPECT_TRUE(r->stale(1));
  EXPECT_FALSE(r->stale(2));
  EXPECT_EQ(r->stale(), 1u);
  r->dispatch();
  EXPECT_EQ(mRunner.runAll(), 1u);
  auto ready = r->collect();
  ASSERT_EQ(ready.size(), 1u);
  EXPECT_TRUE(ready[0].refresh);
  EXPECT_TRUE(r->stale(1));  // until uploaded
  r->markRefreshed(ready[0], kChunkBytes);
  EXPECT_FALSE(r->stale(1));
  EXPECT_EQ(r->stale(), 0u);
}

TEST_F(ResidencyTest, NoLoadStartsWhileTheUploadBacklogIsFull) {
  ResidencyOptions o;
  o.maxInFlight = 4;
  o.maxReady = 2;
  auto r = make(o);
  loadRoot(*r);
  for (uint32_t node = 1; node <= 3; ++node) r->request(node, float(node));
  r->dispatch();
  EXPECT_EQ(mRunner.runAll(), 3u);
  // The frame's upload budget ran out: all three wait, and a new request waits behind them.
  for (ReadyChunk& c : r->collect()) r->returnReady(std::move(c));
  EXPECT_EQ(r->readyWaiting(), 3u);
  r->request(4, 1.0f);
  r->dispatch();
  EXPECT_EQ(r->state(4), ChunkState::kQueued);
  EXPECT_EQ(r->inFlight(), 0u);
  // Uploaded: it starts.
  uploadAll(*r);
  r->request(4, 1.0f);
  r->dispatch();
  EXPECT_EQ(r->state(4), ChunkState::kLoading);
  EXPECT_EQ(mRunner.runAll(), 1u);
}

TEST_F(ResidencyTest, RequestsNobodyRenewsAreCancelled) {
  ResidencyOptions o;
  o.maxInFlight = 1;
  auto r = make(o);
  loadRoot(*r);
  r->request(1, 1.0f);
  r->request(2, 2.0f);
  r->dispatch();  // 1 loading, 2 queued
  r->request(1, 1.0f);
  r->dispatch();  // 2 not wanted any more
  EXPECT_EQ(r->state(2), ChunkState::kAbsent);
  EXPECT_EQ(r->counters().cancelled, 1u);
  mRunner.runAll();
  EXPECT_EQ(mLoadCalls, 2);  // the root and node 1: node 2 was never read
}

TEST_F(ResidencyTest, OnlyChildrenOfResidentChunksAreRequested) {
  auto r = make({});
  loadRoot(*r);
  r->request(5, 1.0f);  // a child of node 1, which is not resident
  r->dispatch();
  EXPECT_EQ(r->state(5), ChunkState::kAbsent);
  EXPECT_EQ(r->inFlight(), 0u);
}

TEST_F(ResidencyTest, FailuresAreLoggedOnceAndRetriedWithBackoff) {
  ResidencyOptions o;
  o.retryFrames = 4;
  auto r = make(o);
  loadRoot(*r);
  mFailing = {1};
  auto frame = [&] {
    mRunner.runAll();
    uploadAll(*r);
    r->request(1, 1.0f);
    r->dispatch();
  };
  frame();  // requested, loading
  int firstRetry = 0, secondRetry = 0;
  for (int f = 1; f <= 40; ++f) {
    const uint64_t before = r->counters().failures;
    frame();
    if (r->state(1) == ChunkState::kLoading && before > 0) {
      if (!firstRetry) {
        firstRetry = f;
      } else if (!secondRetry) {
        secondRetry = f;
      }
    }
  }
  EXPECT_GE(r->counters().failures, 2u);
  EXPECT_EQ(mLog.size(), 1u) << "one line per failing chunk, not per attempt";
  EXPECT_EQ(mLog[0], "chunk 1 is broken");
  ASSERT_GT(firstRetry, 0);
  ASSERT_GT(secondRetry, firstRetry);
  EXPECT_GT(secondRetry - firstRetry, 4) << "the second retry waits longer (backoff)";
  mFailing.clear();
  for (int f = 0; f < 80 && r->state(1) != ChunkState::kResident; ++f) frame();
  EXPECT_EQ(r->state(1), ChunkState::kResident) << "a chunk that reads again is recovered";
}

TEST_F(ResidencyTest, EvictsLeastRecentlyUsedLeavesOfTheResidentSetUnderTheBudget) {
  ResidencyOptions o;
  o.budgetBytes = 5 * kChunkBytes;
  auto r = make(o);
  loadRoot(*r);
  for (uint32_t c = 1; c <= 4; ++c) r->request(c, float(c));
  r->dispatch();
  mRunner.runAll();
  uploadAll(*r);  // root + 4 children: the budget
  EXPECT_TRUE(r->evict().empty()) << "chunks are not evicted in the frame they arrive";
  r->dispatch();
  // This frame uses the root and children 2, 3 and 4 and wants a child of 2; child 1 was last
  // used before: it makes room.
  r->touch(0);
  for (uint32_t c = 2; c <= 4; ++c) r->touch(c);
  r->request(9, 1.0f);
  const auto evicted = r->evict();
  ASSERT_EQ(evicted, std::vector<uint32_t>{1});
  EXPECT_EQ(r->drawable()[1], 0);
  EXPECT_EQ(r->counters().evictions, 1u);
  EXPECT_EQ(r->counters().residentBytes, 4 * kChunkBytes);
  r->dispatch();

  // A chunk with resident children is never evicted before them, and the root never.
  r->request(5, 1.0f);  // child of node 1? no: node 1 is absent, so this is ignored
  r->request(9, 1.0f);  // child of node 2, which now fits
  r->dispatch();
  mRunner.runAll();
  uploadAll(*r);
  r->dispatch();
  const auto more = r->evict();  // nothing touched this frame
  for (uint32_t e : more) {
    EXPECT_NE(e, 0u);
    EXPECT_NE(e, 2u) << "node 2 has a resident child";
  }
  EXPECT_LE(r->counters().residentBytes, o.budgetBytes);
}

// Loads reserve room for what they bring: they start only while the resident chunks and the
// loads in flight fit, so the budget holds.
TEST_F(ResidencyTest, LoadsInFlightCountAgainstTheBudget) {
  ResidencyOptions o;
  o.budgetBytes = 3 * kChunkBytes;
  o.maxInFlight = 8;
  auto r = make(o);
  loadRoot(*r);
  for (uint32_t c = 1; c <= 4; ++c) r->request(c, float(c));
  r->dispatch();
  EXPECT_EQ(r->inFlight(), 2u) << "room for two more chunks of the root's size";
  mRunner.runAll();
  uploadAll(*r);
  EXPECT_LE(r->counters().residentBytesMax, o.budgetBytes);
}

// A wanted chunk is in use: when what is wanted does not fit, nothing wanted is evicted to
// load something else wanted (that would load and evict the same chunks every frame).
TEST_F(ResidencyTest, WantedChunksAreNotEvictedForOtherWantedOnes) {
  ResidencyOptions o;
  o.budgetBytes = 3 * kChunkBytes;
  auto r = make(o);
  loadRoot(*r);
  for (uint32_t c = 1; c <= 2; ++c) r->request(c, float(c));
  r->dispatch();
  mRunner.runAll();
  uploadAll(*r);
  r->dispatch();
  for (int frame = 0; frame < 5; ++frame) {
    r->touch(0);
    for (uint32_t c = 1; c <= 4; ++c) r->request(c, float(c));
    EXPECT_TRUE(r->evict().empty()) << "frame " << frame;
    r->dispatch();
    mRunner.runAll();
    uploadAll(*r);
  }
  EXPECT_EQ(r->counters().evictions, 0u);
  EXPECT_EQ(r->counters().loads, 3u);  // the root and the first two
}

TEST_F(ResidencyTest, NoNewLoadsStartOverTheBudget) {
  ResidencyOptions o;
  o.budgetBytes = kChunkBytes;  // the root alone fills it
  auto r = make(o);
  loadRoot(*r);
  r->request(1, 1.0f);
  r->dispatch();
  EXPECT_EQ(r->inFlight(), 0u);
  EXPECT_EQ(r->state(1), ChunkState::kQueued);
}

// Loads start only below the budget and eviction used to stop at it: a budget filled to the
// byte kept a wanted chunk queued for good, with unused chunks resident.
TEST_F(ResidencyTest, AFullBudgetMakesRoomForWhatIsWanted) {
  ResidencyOptions o;
  o.budgetBytes = 3 * kChunkBytes;
  auto r = make(o);
  loadRoot(*r);
  loadChildren(*r, 2);  // root + 2 children: exactly the budget
  EXPECT_TRUE(r->evict().empty()) << "nothing is wanted: nothing to make room for";
  r->dispatch();
  // Next frame child 2 is no longer used and child 3 is wanted.
  r->touch(0);
  r->touch(1);
  r->request(3, 1.0f);
  EXPECT_EQ(r->evict(), std::vector<uint32_t>{2});
  r->dispatch();
  EXPECT_EQ(r->state(3), ChunkState::kLoading);
  EXPECT_LE(r->counters().residentBytes, o.budgetBytes);
  mRunner.runAll();  // the residency waits for its loads when it goes
}

// While the uploads are behind (maxReady waiting), a wanted load could not start anyway:
// no room is made for it, or what is evicted for it would be wanted back meanwhile.
TEST_F(ResidencyTest, NoRoomIsMadeForALoadThatCouldNotStart) {
  ResidencyOptions o;
  o.budgetBytes = 4 * kChunkBytes;
  o.maxReady = 1;
  auto r = make(o);
  loadRoot(*r);
  loadChildren(*r, 2);
  r->dispatch();
  r->request(3, 1.0f);
  r->dispatch();
  mRunner.runAll();
  for (ReadyChunk& c : r->collect()) r->returnReady(std::move(c));  // no upload this frame
  EXPECT_EQ(r->counters().residentBytes, o.budgetBytes);
  // Next frame child 2 is no longer used and child 4 is wanted: it waits for the upload.
  r->touch(0);
  r->touch(1);
  r->request(3, 1.0f);
  r->request(4, 2.0f);
  EXPECT_TRUE(r->evict().empty());
  r->dispatch();
  EXPECT_EQ(r->state(2), ChunkState::kResident);
  EXPECT_EQ(r->state(4), ChunkState::kQueued);
  // Uploaded: room is made and it starts.
  uploadAll(*r);
  r->touch(0);
  r->touch(1);
  r->touch(3);
  r->request(4, 2.0f);
  EXPECT_EQ(r->evict(), std::vector<uint32_t>{2});
  r->dispatch();
  EXPECT_EQ(r->state(4), ChunkState::kLoading);
  mRunner.runAll();
}

TEST_F(ResidencyTest, SelectionDrawsTheResidentParentUntilItsChildrenArrive) {
  ResidencyOptions o;
  o.maxInFlight = 8;
  auto r = make(o);
  loadRoot(*r);
  const View close = viewFrom({512, 512, 40}, {600, 600, 0});
  SelectionOptions s;
  s.tau = 1.0;
  s.drawable = r->drawable();
  std::vector<SelectedChunk> out;
  out.reserve(mTree.nodes().size());
  SelectionStats stats = selectChunks(mTree, close, s, out);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].node, 0u);
  EXPECT_EQ(stats.coarserThanWanted, 1u);
  // Children come in: each frame asks for the children of chunks drawn coarser than wanted.
  int frames = 0;
  for (; frames < 100 && stats.coarserThanWanted > 0; ++frames) {
    for (const SelectedChunk& c : out) {
      const ChunkNode& n = mTree.node(c.node);
      for (uint32_t k = 0; k < n.childCount; ++k) r->request(n.firstChild + k, 1.0f);
    }
    r->dispatch();
    mRunner.runAll();
    uploadAll(*r);
    stats = selectChunks(mTree, close, s, out);
    for (const SelectedChunk& c : out) EXPECT_EQ(r->drawable()[c.node], 1) << c.node;
  }
  EXPECT_EQ(stats.coarserThanWanted, 0u) << "after " << frames << " frames";
  EXPECT_GT(out.size(), 4u);
}

TEST(ThreadPool, RunsEveryTaskOnWorkerThreads) {
  std::atomic<int> ran{0};
  {
    ThreadPool pool(3);
    for (int i = 0; i < 1000; ++i) pool.post([&] { ++ran; });
  }  // the destructor finishes the queue
  EXPECT_EQ(ran, 1000);
}

// The real thing: loads on a pool of threads while the "render thread" requests, uploads and
// evicts, frame after frame, under a budget that forces eviction. Checks the invariants
// selection relies on (ThreadSanitizer runs this in CI).
TEST(ResidencyThreaded, ManyFramesOnAThreadPoolKeepTheInvariants) {
  FullTree full(5);
  ChunkTree tree = full.tree();
  std::atomic<int> loads{0};
  ThreadPool pool(3);
  ResidencyOptions o;
  o.budgetBytes = 12 * 1000;
  o.maxInFlight = 6;
  Residency r(
      tree,
      [&](uint32_t node) -> Result<LoadedChunk> {
        ++loads;
        if (node % 17 == 5) return Error{"flaky chunk " + std::to_string(node)};
        std::this_thread::sleep_for(std::chrono::microseconds(50 + node % 7 * 20));
        return LoadedChunk{std::make_unique<FakePayload>(), 1000, 1000, {}};
      },
      pool, o);
  ASSERT_TRUE(r.loadNow(0).ok());
  r.markLoadedNow(0, 1000);
  SelectionOptions s;
  s.tau = 1.0;
  std::vector<SelectedChunk> out;
  out.reserve(tree.nodes().size());
  // At least 400 frames, and on until the budget has forced evictions and a failure was seen
  // (how soon depends on how fast the loader threads get the CPU).
  for (int frame = 0;
       frame < 5000 && (frame < 400 || r.counters().evictions == 0 || r.counters().failures == 0);
       ++frame) {
    for (ReadyChunk& c : r.collect()) r.markResident(c, 1000);
    const double t = frame * 0.05;
    const View view =
        viewFrom({512 + 400 * std::cos(t), 512 + 400 * std::sin(t), 30}, {512, 512, 0});
    s.drawable = r.drawable();
    const SelectionStats stats = selectChunks(tree, view, s, out);
    ASSERT_GT(stats.selected, 0u);
    for (const SelectedChunk& c : out) {
      ASSERT_EQ(r.drawable()[c.node], 1) << "selected a chunk that is not resident";
      for (uint32_t i = c.node; i != kNoNode; i = tree.node(i).parent) {
        ASSERT_EQ(r.state(i), ChunkState::kResident) << "an ancestor is not resident";
        r.touch(i);
      }
      const ChunkNode& n = tree.node(c.node);
      for (uint32_t k = 0; k < n.childCount; ++k) r.request(n.firstChild + k, float(c.node));
    }
    r.evict();
    r.dispatch();
    std::this_thread::sleep_for(std::chrono::microseconds(300));  // the frame's drawing
  }
  EXPECT_GT(r.counters().evictions, 0u) << "the budget never forced an eviction";
  EXPECT_GT(r.counters().failures, 0u);
  EXPECT_LE(r.counters().residentBytesMax, o.budgetBytes + o.maxInFlight * 1000);
}

}  // namespace
}  // namespace terralod
