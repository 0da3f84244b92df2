// The frame driver flown through a recorded flight with no threads and no GL: a tileset of a
// test-only chunk kind (blob_kind.h) written to a file, an inline task runner, a fake clock and
// a recording backend. The same flight gives the same selections, morphs, loads and evictions
// every run; the budgets hold; the resident set stays closed under parents.

#include "terralod/runtime/frame_driver.h"

#include <gtest/gtest.h>

#include <filesystem>

#include "blob_kind.h"
#include "terralod/runtime/flight.h"

namespace terralod {
namespace {

constexpr int kLevels = 6;  // 1365 chunks

std::string tilesetPath(const std::string& name) {
  return (std::filesystem::path(::testing::TempDir()) / name).string();
}

// One run of the flight: what each frame drew, uploaded and released, and the counters.
struct FlightRun {
  std::vector<RecordedFrame> frames;  // the backend's: [0] the roots
  std::vector<RecordedFrame> drawn;   // per update: the draws the kind added to the frame
  std::vector<UpdateStats> stats;
  ResidencyCounters counters;
  size_t readyWaiting = 0;              // loaded, not uploaded, at the end
  std::vector<uint64_t> residentBytes;  // after each update
  std::vector<uint64_t> keptBytes;      // after each update: uploaded chunks plus shared
};

Flight recordedFlight(const ChunkTree& tree) {
  // As a recorded flight is stored: JSON, read back.
  const Flight flight = autoFlight(tree, 320, 240, 60.0, 300);
  return parseFlight(flightToJson(flight), "flight.json").value();
}

// `renderMs`: what drawing each frame takes on the clock after its update. `stillFrames` > 0:
// the flight's first camera that many times instead. `sharedPerGroup`: BlobKind's.
FlightRun fly(const std::string& path, FrameDriverOptions options,
              const std::function<void(const FrameDriver&, const ChunkTree&)>& check = {},
              double renderMs = 0.0, size_t stillFrames = 0, uint64_t sharedPerGroup = 0) {
  auto reader = TilesetReader::openFile(path);
  EXPECT_TRUE(reader.ok()) << reader.error().message;
  const ChunkTree tree((*reader)->header(), (*reader)->nodes());
  InlineRunner runner;
  FakeClock clock(&runner);
  RecordingBackend backend(clock);
  BlobKind kind(backend);
  kind.sharedPerGroup = sharedPerGroup;
  ChunkKinds kinds;
  kinds.add(kind);
  auto driver = FrameDriver::create(**reader, tree, kinds, runner, clock, std::move(options));
  EXPECT_TRUE(driver.ok()) << driver.error().message;
  FlightRun run;
  KindRuns runs;
  SelectionOptions selection;
  selection.tau = 2.0;
  std::vector<Camera> cameras = flightCameras(recordedFlight(tree));
  if (stillFrames > 0) cameras.assign(stillFrames, cameras.front());
  for (const Camera& camera : cameras) {
    run.stats.push_back((*driver)->update(makeView(camera).value(), selection));
    RecordedFrame frame;
    runs.split(tree, (*driver)->selected());
    for (const KindRuns::Run& r : runs.runs()) {
      EXPECT_EQ(r.kind, kBlobMeshKind);
      kind.addDraws(frame, r.chunks);
    }
    run.drawn.push_back(std::move(frame));
    run.residentBytes.push_back((*driver)->residency().counters().residentBytes);
    run.keptBytes.push_back(kind.uploaded.size() * kBlobPayloadBytes + kind.sharedBytes());
    if (check) check(**driver, tree);
    clock.advance(renderMs);
    runner.runAll();  // the loads dispatched this frame finish before the next
  }
  run.counters = (*driver)->residency().counters();
  run.readyWaiting = (*driver)->residency().readyWaiting();
  run.frames = backend.frames;
  return run;
}

FrameDriverOptions smallBudget() {
  FrameDriverOptions o;
  // Exactly 100 chunks: a budget filled to the byte still makes room for what is wanted.
  o.cacheBytes = 100 * kBlobPayloadBytes;
  o.maxInFlight = 8;
  o.uploadMillisecondsPerFrame = 4.0;  // the backend takes 1 ms per upload: 5 per frame
  return o;
}

TEST(FrameDriver, ARecordedFlightLoadsSelectsAndEvictsTheSameEveryRun) {
  const std::string path = writeBlobTileset(tilesetPath("driver_same.tlod"), kLevels);
  const FlightRun a = fly(path, smallBudget());
  const FlightRun b = fly(path, smallBudget());
  ASSERT_EQ(a.drawn.size(), 300u);
  ASSERT_EQ(a.frames.size(), b.frames.size());
  for (size_t f = 0; f < a.frames.size(); ++f) EXPECT_TRUE(a.frames[f] == b.frames[f]) << f;
  for (size_t f = 0; f < a.drawn.size(); ++f) {
    EXPECT_TRUE(a.drawn[f] == b.drawn[f]) << f;
    EXPECT_EQ(a.stats[f].selection.selected, b.stats[f].selection.selected) << f;
    EXPECT_EQ(a.stats[f].easing, b.stats[f].easing) << f;
  }
  EXPECT_EQ(a.counters.loads, b.counters.loads);
  EXPECT_EQ(a.counters.evictions, b.counters.evictions);
  EXPECT_EQ(a.counters.cancelled, b.counters.cancelled);
  EXPECT_EQ(a.counters.residentBytesMax, b.counters.residentBytesMax);

  // It did something: chunks loaded, evicted under the small budget, late splits eased.
  EXPECT_GT(a.counters.loads, 150u);
  EXPECT_GT(a.counters.evictions, 20u);
  uint32_t easing = 0, deepest = 0;
  for (const UpdateStats& s : a.stats) {
    easing += s.easing;
    deepest = std::max<uint32_t>(deepest, uint32_t(s.selection.deepestLevel));
  }
  EXPECT_GT(easing, 0u);
  EXPECT_GE(deepest, uint32_t(kLevels - 2));
  // The backend saw what the driver counted.
  uint64_t uploads = 0, releases = 0;
  for (const RecordedFrame& f : a.frames) {
    uploads += f.uploads.size();
    releases += f.releases.size();
  }
  EXPECT_EQ(uploads, a.counters.loads - a.counters.discarded - a.readyWaiting);
  EXPECT_EQ(releases, a.counters.evictions);
}

// A still camera that wants more than the budget settles: once loads stop, nothing is
// evicted and loaded again (a split parent's children out of view stay resident with the
// ones drawn; evicting them merged the parent, which wanted them again, over and over).
TEST(FrameDriver, AStillCameraOverTheBudgetSettles) {
  const std::string path = writeBlobTileset(tilesetPath("driver_still.tlod"), kLevels);
  FrameDriverOptions options = smallBudget();
  options.cacheBytes = 40 * kBlobPayloadBytes;
  size_t settledAt = 0;
  const FlightRun run = fly(
      path, options,
      [&](const FrameDriver& driver, const ChunkTree&) {
        if (settledAt == 0 && driver.residency().frame() > 60)
          settledAt = driver.residency().counters().loads;
      },
      0.0, 120);
  EXPECT_GT(run.counters.loads, 30u);  // it filled the budget
  EXPECT_EQ(run.counters.loads, settledAt) << "loads after the first 60 frames";
  EXPECT_GT(run.stats.back().selection.coarserThanWanted, 0u) << "the budget is too small";
  EXPECT_LE(run.counters.residentBytesMax, options.cacheBytes);
}

TEST(FrameDriver, KeepsTheBudgetsAndTheResidentSetClosedUnderParents) {
  const std::string path = writeBlobTileset(tilesetPath("driver_budget.tlod"), kLevels);
  const FrameDriverOptions options = smallBudget();
  const FlightRun run = fly(path, options, [](const FrameDriver& driver, const ChunkTree& tree) {
    const Residency& r = driver.residency();
    for (uint32_t i = 0; i < tree.nodes().size(); ++i) {
      const uint32_t parent = tree.node(i).parent;
      if (r.state(i) == ChunkState::kResident && parent != kNoNode) {
        EXPECT_EQ(r.state(parent), ChunkState::kResident) << "node " << i;
      }
    }
    for (const SelectedChunk& c : driver.selected())
      EXPECT_EQ(r.state(c.node), ChunkState::kResident) << "drawn node " << c.node;
    // The occluder grids of the resident chunks, and only theirs, are kept.
    uint64_t resident = 0;
    for (uint32_t i = 0; i < tree.nodes().size(); ++i)
      resident += r.state(i) == ChunkState::kResident ? 1 : 0;
    EXPECT_EQ(driver.occluderBytes(), resident * blobOccluders().bytes());
  });
  for (size_t f = 0; f < run.residentBytes.size(); ++f)
    EXPECT_LE(run.residentBytes[f], options.cacheBytes) << "frame " << f;
  // 1 ms per upload against 4 ms per frame: never more than 5 uploads in a frame.
  for (size_t f = 1; f < run.frames.size(); ++f) EXPECT_LE(run.frames[f].uploads.size(), 5u) << f;
  size_t fullFrames = 0;
  for (const UpdateStats& s : run.stats) fullFrames += s.uploads == 5 ? 1 : 0;
  EXPECT_GT(fullFrames, 0u) << "the upload budget never bit: nothing tested";
}

// What a kind holds besides its chunks (VIPM super-chunk blocks' spare room) is in the budget:
// chunks plus shared memory stay within it every frame.
TEST(FrameDriver, MemoryAKindSharesBetweenChunksCountsAgainstTheBudget) {
  const std::string path = writeBlobTileset(tilesetPath("driver_shared.tlod"), kLevels);
  const FrameDriverOptions options = smallBudget();
  const FlightRun run = fly(path, options, {}, 0.0, 0, kBlobPayloadBytes);
  uint64_t keptMax = 0;
  for (size_t f = 0; f < run.keptBytes.size(); ++f) {
    EXPECT_LE(run.keptBytes[f], options.cacheBytes) << "frame " << f;
    EXPECT_LE(run.residentBytes[f], options.cacheBytes) << "frame " << f;
    keptMax = std::max(keptMax, run.keptBytes[f]);
  }
  EXPECT_GT(run.counters.evictions, 20u);
  EXPECT_GT(run.counters.sharedBytes, 0u);
  EXPECT_GT(keptMax, options.cacheBytes * 3 / 4) << "the budget never filled: nothing tested";
}

TEST(FrameDriver, SlowFramesGiveUploadsAShareOfTheirInterval) {
  // Frames that take 96 ms to draw (software rendering): a tenth of the last interval, about
  // 10 ms, is more than the 4 ms floor, so up to 11 uploads of 1 ms fit, and the stream keeps up.
  const std::string path = writeBlobTileset(tilesetPath("driver_slow.tlod"), kLevels);
  auto mostUploads = [](const FlightRun& run) {
    size_t most = 0;
    for (size_t f = 1; f < run.frames.size(); ++f)
      most = std::max(most, run.frames[f].uploads.size());
    return most;
  };
  const FlightRun slow = fly(path, smallBudget(), {}, 96.0);
  EXPECT_GT(mostUploads(slow), 5u);
  EXPECT_LE(mostUploads(slow), 12u);  // 10.8 ms at most (96 + 12 uploads), then one more
  FrameDriverOptions floorOnly = smallBudget();
  floorOnly.uploadFrameShare = 0.0;
  EXPECT_LE(mostUploads(fly(path, floorOnly, {}, 96.0)), 5u);
  // Fast frames keep the floor.
  EXPECT_LE(mostUploads(fly(path, smallBudget())), 5u);
}

TEST(FrameDriver, SplitsOnTimeAreNotCountedAsEasing) {
  // Loads and uploads without limit: once the first view has arrived (the flight starts from
  // the roots alone, frames 0-17 here), every child is resident before its parent splits, so
  // no split is late. Each starts within a hair of its schedule (its parent's ρ passed τ
  // between two frames) and none counts as easing; with a tight budget some do (the first
  // test).
  const std::string path = writeBlobTileset(tilesetPath("driver_on_time.tlod"), kLevels);
  FrameDriverOptions options;
  options.cacheBytes = uint64_t(1) << 40;
  options.maxInFlight = 100000;
  options.uploadMillisecondsPerFrame = 1e9;
  constexpr size_t kSettled = 30;
  size_t splits = 0, frame = 1;
  std::vector<uint8_t> drawnBefore;
  const FlightRun run = fly(path, options, [&](const FrameDriver& driver, const ChunkTree& tree) {
    std::vector<uint8_t> drawn(tree.nodes().size(), 0);
    for (const SelectedChunk& c : driver.selected()) drawn[c.node] = 1;
    if (!drawnBefore.empty() && frame++ >= kSettled)
      for (const SelectedChunk& c : driver.selected()) {
        const uint32_t parent = tree.node(c.node).parent;
        splits += !drawnBefore[c.node] && parent != kNoNode && drawnBefore[parent] ? 1 : 0;
      }
    drawnBefore = std::move(drawn);
  });
  EXPECT_GT(splits, 20u);
  for (size_t f = kSettled; f < run.stats.size(); ++f) {
    EXPECT_EQ(run.stats[f].selection.coarserThanWanted, 0u) << f;
    EXPECT_EQ(run.stats[f].easing, 0u) << f;
  }
}

TEST(FrameDriver, CompleteFramesWaitUntilWhatTheyWantIsResident) {
  const std::string path = writeBlobTileset(tilesetPath("driver_complete.tlod"), kLevels);
  FrameDriverOptions options;
  options.completeness = FrameCompleteness::kComplete;
  const FlightRun run = fly(path, options);
  bool waited = false;
  for (size_t f = 0; f < run.stats.size(); ++f) {
    EXPECT_EQ(run.stats[f].selection.coarserThanWanted, 0u) << f;
    EXPECT_EQ(run.stats[f].easing, 0u) << f;  // complete frames show the settled selection
    waited = waited || run.stats[f].waitedOnIo;
  }
  EXPECT_TRUE(waited);
}

TEST(FrameDriver, SaysSoWhenTheRootsAloneFillTheBudget) {
  // Roots are never evicted: a budget they fill can load nothing finer, which a user would
  // otherwise only see as a coarse picture.
  const std::string path = writeBlobTileset(tilesetPath("driver_roots.tlod"), kLevels);
  constexpr uint64_t kRoots = 1;  // writeBlobTileset's quadtree has one root
  auto linesWithBudget = [&](uint64_t bytes) {
    FrameDriverOptions o;
    o.cacheBytes = bytes;
    std::vector<std::string> lines;
    o.log = [&lines](const std::string& line) { lines.push_back(line); };
    const FlightRun run = fly(path, o);
    return std::pair(lines, run.counters.loads);
  };
  const auto [full, loadsFull] = linesWithBudget(kRoots * kBlobPayloadBytes);
  ASSERT_EQ(full.size(), 1u);
  EXPECT_NE(full[0].find(path), std::string::npos) << full[0];
  EXPECT_NE(full[0].find("roots alone take"), std::string::npos) << full[0];
  EXPECT_NE(full[0].find("--cache-mb"), std::string::npos) << full[0];
  EXPECT_EQ(loadsFull, kRoots);  // as it says: nothing finer loaded
  const auto [room, loadsRoom] = linesWithBudget(100 * kBlobPayloadBytes);
  EXPECT_TRUE(room.empty());
  EXPECT_GT(loadsRoom, kRoots);
}

TEST(FrameDriver, RefusesATilesetWithAMeshKindNobodyRegistered) {
  const std::string path = writeBlobTileset(tilesetPath("driver_unknown.tlod"), 2);
  auto reader = TilesetReader::openFile(path);
  ASSERT_TRUE(reader.ok()) << reader.error().message;
  const ChunkTree tree((*reader)->header(), (*reader)->nodes());
  InlineRunner runner;
  FakeClock clock;
  auto driver = FrameDriver::create(**reader, tree, ChunkKinds{}, runner, clock, {});
  ASSERT_FALSE(driver.ok());
  EXPECT_NE(driver.error().message.find(path), std::string::npos) << driver.error().message;
  EXPECT_NE(driver.error().message.find("no kind registered for mesh kind 7"), std::string::npos)
      << driver.error().message;
  // The static kind's reader refuses it too, clearly.
  auto data = (*reader)->readChunkData(0);
  ASSERT_FALSE(data.ok());
  EXPECT_NE(data.error().message.find("chunk 0 has mesh kind 7, not static RTIN"),
            std::string::npos)
      << data.error().message;
}

TEST(FrameDriver, AChunkItsKindCannotDecodeFailsOnTheLoaderAndIsNeverDrawn) {
  // Node 1's blob is node 2's: the kind refuses it on the loader; the frames go on without it.
  const std::string path = writeBlobTileset(tilesetPath("driver_bad_blob.tlod"), kLevels, 1);
  FrameDriverOptions options = smallBudget();
  options.log = [](const std::string& line) {
    EXPECT_NE(line.find("chunk 1 is another's"), std::string::npos) << line;
  };
  const FlightRun run = fly(path, options);
  EXPECT_GT(run.counters.failures, 0u);
  for (const RecordedFrame& f : run.frames)
    for (uint32_t node : f.uploads) EXPECT_NE(node, 1u);
  for (const RecordedFrame& f : run.drawn) {
    EXPECT_FALSE(f.draws.empty());
    for (const SelectedChunk& c : f.draws) EXPECT_NE(c.node, 1u);
  }
}

TEST(KindRuns, GroupsAMixedSelectionByKindInSelectionOrder) {
  FullTree full(2);
  full.nodes[2].meshKind = kBlobMeshKind;
  full.nodes[4].meshKind = kBlobMeshKind;
  const ChunkTree tree = full.tree();
  const std::vector<SelectedChunk> chunks = {{1, 0.f}, {2, 0.f}, {3, 0.f}, {4, 0.f}};
  KindRuns runs;
  runs.split(tree, chunks);
  ASSERT_EQ(runs.runs().size(), 2u);
  EXPECT_EQ(runs.runs()[0].kind, MeshKind::kStaticRtin);
  EXPECT_EQ(runs.runs()[0].chunks[0].node, 1u);
  EXPECT_EQ(runs.runs()[0].chunks[1].node, 3u);
  EXPECT_EQ(runs.runs()[1].kind, kBlobMeshKind);
  EXPECT_EQ(runs.runs()[1].chunks[0].node, 2u);
  EXPECT_EQ(runs.runs()[1].chunks[1].node, 4u);
  // One kind: one run over the selection itself.
  const std::vector<SelectedChunk> one = {{1, 0.f}, {3, 0.f}};
  runs.split(tree, one);
  ASSERT_EQ(runs.runs().size(), 1u);
  EXPECT_EQ(runs.runs()[0].chunks.data(), one.data());
}

}  // namespace
}  // namespace terralod

namespace terralod {
namespace {

// A driver over the blob kind with the small budget, for the edit tests.
struct BlobDriver {
  BlobDriver(const TilesetReader& reader, const ChunkTree& tree) {
    kinds.add(kind);
    driver = FrameDriver::create(reader, tree, kinds, runner, clock, smallBudget()).value();
  }
  InlineRunner runner;
  FakeClock clock{&runner};
  RecordingBackend backend{clock};
  BlobKind kind{backend};
  ChunkKinds kinds;
  std::unique_ptr<FrameDriver> driver;
};

// An edit's nodes (replaceNodes): resident ones are decoded again on the loader threads and
// swapped in by a later update while their old payload keeps being drawn; absent ones load
// the new bytes when wanted; every replaced node's last upload is its new bytes.
TEST(FrameDriver, ReplacedNodesAreSwappedInWhileTheOldOnesAreDrawn) {
  const std::string path = writeBlobTileset(tilesetPath("driver_replace.tlod"), kLevels);
  auto reader = TilesetReader::openFile(path).value();
  const ChunkTree tree(reader->header(), reader->nodes());
  BlobDriver rig(*reader, tree);
  InlineRunner& runner = rig.runner;
  BlobKind& kind = rig.kind;
  FrameDriver* driver = rig.driver.get();
  SelectionOptions selection;
  selection.tau = 2.0;
  const std::vector<Camera> cameras = flightCameras(recordedFlight(tree));
  constexpr size_t kEditFrame = 120;
  std::vector<uint32_t> replaced, residentAtEdit;
  size_t swappedAt = 0;
  for (size_t f = 0; f < cameras.size(); ++f) {
    driver->update(makeView(cameras[f]).value(), selection);
    const Residency& r = driver->residency();
    if (f == kEditFrame) {
      // Every drawn node, a root, and the first node nobody has loaded.
      std::vector<NodeReplacement> edit;
      for (const SelectedChunk& c : driver->selected()) replaced.push_back(c.node);
      replaced.push_back(0);
      for (uint32_t i = 0; i < tree.nodes().size(); ++i)
        if (r.state(i) == ChunkState::kAbsent) {
          replaced.push_back(i);
          break;
        }
      std::sort(replaced.begin(), replaced.end());
      replaced.erase(std::unique(replaced.begin(), replaced.end()), replaced.end());
      for (uint32_t node : replaced) {
        NodeReplacement n;
        n.node = node;
        n.record = reader->nodes()[node];
        n.bytes.bytes = blobFor(node, 0xAB);
        n.bytes.meshBytes = uint32_t(n.bytes.bytes.size());
        edit.push_back(std::move(n));
        if (r.state(node) == ChunkState::kResident) residentAtEdit.push_back(node);
      }
      ASSERT_GT(residentAtEdit.size(), 1u);
      ASSERT_LT(residentAtEdit.size(), replaced.size());  // one was absent
      driver->replaceNodes(std::move(edit));
      EXPECT_GT(driver->pendingReplacements(), 0u);
    }
    if (f > kEditFrame) {
      // The drawn chunks stay drawn meanwhile (old payloads until swapped; the flight may
      // evict a replaced node it no longer wants, which then loads the new bytes).
      for (const SelectedChunk& c : driver->selected())
        EXPECT_EQ(r.state(c.node), ChunkState::kResident) << "node " << c.node << " frame " << f;
      if (swappedAt == 0 && driver->pendingReplacements() == 0) {
        swappedAt = f;
        // None pending means every resident replaced node draws its new bytes already.
        for (uint32_t node : replaced)
          if (r.state(node) == ChunkState::kResident) {
            EXPECT_EQ(kind.uploadedFiller[node], 0xAB) << "node " << node << " frame " << f;
          }
      }
      if (swappedAt == 0) {
        size_t old = 0;
        for (uint32_t node : residentAtEdit)
          old += r.state(node) == ChunkState::kResident && kind.uploadedFiller[node] != 0xAB;
        EXPECT_GT(old, 0u) << "pending replacements but none left to swap, frame " << f;
      }
    }
    runner.runAll();
  }
  ASSERT_GT(swappedAt, kEditFrame) << "the replaced nodes were never all swapped in";
  // Decoded beside the loads, uploaded within the per-frame budget (5 uploads here, shared
  // with the flight's own loads).
  EXPECT_LE(swappedAt, kEditFrame + 2 + residentAtEdit.size()) << residentAtEdit.size();
  // Every replaced node drawn since (resident now, or loaded later) shows its new bytes.
  const Residency& r = driver->residency();
  size_t swapped = 0;
  for (uint32_t node : replaced)
    if (r.state(node) == ChunkState::kResident) {
      EXPECT_EQ(kind.uploadedFiller[node], 0xAB) << node;
      ++swapped;
    }
  EXPECT_GT(swapped, 0u);
  EXPECT_EQ(kind.uploadedFiller[0], 0xAB);  // the root: resident throughout, so swapped
}

// A new record alone (an edit moved a flange depth beside it): a drawn chunk whose kind can
// takes it in place, with nothing decoded or uploaded again; otherwise it is swapped in as
// new bytes would be.
TEST(FrameDriver, ANewRecordAloneIsTakenInPlaceWhereTheKindCan) {
  const std::string path = writeBlobTileset(tilesetPath("driver_record.tlod"), kLevels);
  auto reader = TilesetReader::openFile(path).value();
  const ChunkTree tree(reader->header(), reader->nodes());
  for (const bool takes : {true, false}) {
    SCOPED_TRACE(takes ? "the kind takes records" : "the kind does not");
    BlobDriver rig(*reader, tree);
    InlineRunner& runner = rig.runner;
    BlobKind& kind = rig.kind;
    kind.takesRecords = takes;
    FrameDriver* driver = rig.driver.get();
    SelectionOptions selection;
    selection.tau = 2.0;
    const std::vector<Camera> cameras = flightCameras(recordedFlight(tree));
    for (size_t f = 0; f < 60; ++f) {
      driver->update(makeView(cameras[f]).value(), selection);
      runner.runAll();
    }
    const Residency& r = driver->residency();
    std::vector<NodeReplacement> edit;
    std::vector<uint32_t> drawn;
    for (const SelectedChunk& c : driver->selected()) {
      NodeReplacement n;
      n.node = c.node;
      n.record = reader->nodes()[c.node];
      n.record.maxSkirtDepth += 7.0f;
      n.bytes.bytes = blobFor(c.node);
      n.bytes.meshBytes = uint32_t(n.bytes.bytes.size());
      n.part = ReplacedPart::kRecord;
      edit.push_back(std::move(n));
      drawn.push_back(c.node);
    }
    ASSERT_GT(drawn.size(), 1u);
    const uint64_t loads = r.counters().loads;
    driver->replaceNodes(std::move(edit));
    if (takes) {
      EXPECT_EQ(driver->pendingReplacements(), 0u);
      for (uint32_t node : drawn)
        EXPECT_EQ(kind.recordsInPlace[node].maxSkirtDepth,
                  reader->nodes()[node].maxSkirtDepth + 7.0f)
            << node;
    } else {
      EXPECT_EQ(driver->pendingReplacements(), drawn.size());
      EXPECT_TRUE(kind.recordsInPlace.empty());
    }
    EXPECT_EQ(r.counters().loads, loads);
  }
}

}  // namespace
}  // namespace terralod
