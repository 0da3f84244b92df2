#pragma once
// A test-only chunk kind and a recording, no-GL backend, to prove the ChunkKind seam:
//
//   - BlobKind (MeshKind 7): a trivial blob format, "BLOB", the node index (u32) and
//     `payloadBytes` bytes of filler; written into a real tileset file by writeBlobTileset
//     (TilesetWriter, a FullTree's node table). Decoding checks the magic and the node.
//   - RecordingBackend: what a GPU backend would do, recorded per frame (uploads, releases,
//     draws); each upload advances a fake clock by 1 ms, so the per-frame upload budget bites.

#include <gtest/gtest.h>

#include <cstring>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "terralod/format/tileset_reader.h"
#include "terralod/format/tileset_writer.h"
#include "terralod/runtime/chunk_kind.h"
#include "terralod/runtime/frame_clock.h"
#include "terralod/runtime/occluder_grid.h"
#include "terralod/runtime/task_runner.h"
#include "test_tree.h"

namespace terralod {

inline constexpr MeshKind kBlobMeshKind = static_cast<MeshKind>(7);
inline constexpr uint32_t kBlobPayloadBytes = 1000;

/// Time moves only when told: by 1 ms per upload (RecordingBackend), and by each sleep, which
/// also runs the inline runner's loads (a complete frame waiting for them).
class FakeClock final : public FrameClock {
 public:
  explicit FakeClock(InlineRunner* runner = nullptr) : mRunner(runner) {}
  double nowMilliseconds() override { return mNow; }
  void sleepMicroseconds(double microseconds) override {
    mNow += microseconds / 1000.0;
    ++sleeps;
    if (mRunner) mRunner->runAll();
  }
  void advance(double milliseconds) { mNow += milliseconds; }
  int sleeps = 0;

 private:
  InlineRunner* mRunner;
  double mNow = 0;
};

/// One frame as the recording backend saw it.
struct RecordedFrame {
  std::vector<uint32_t> uploads, releases;
  std::vector<SelectedChunk> draws;
  bool operator==(const RecordedFrame& o) const {
    auto same = [](const std::vector<SelectedChunk>& a, const std::vector<SelectedChunk>& b) {
      if (a.size() != b.size()) return false;
      for (size_t i = 0; i < a.size(); ++i)
        if (a[i].node != b[i].node || a[i].morph != b[i].morph) return false;
      return true;
    };
    return uploads == o.uploads && releases == o.releases && same(draws, o.draws);
  }
};

class RecordingBackend {
 public:
  explicit RecordingBackend(FakeClock& clock) : mClock(clock) { frames.emplace_back(); }
  void beginFrame() { frames.emplace_back(); }
  void upload(uint32_t node) {
    frames.back().uploads.push_back(node);
    mClock.advance(1.0);
  }
  void release(uint32_t node) { frames.back().releases.push_back(node); }
  void draw(std::span<const SelectedChunk> chunks) {
    frames.back().draws.insert(frames.back().draws.end(), chunks.begin(), chunks.end());
  }
  std::vector<RecordedFrame> frames;  ///< [0]: the roots, before the first frame

 private:
  FakeClock& mClock;
};

struct BlobPayload final : ChunkPayload {
  uint32_t node = 0;
  uint8_t filler = 0;  ///< the blob's first filler byte (a replaced node's tells its version)
};

inline std::vector<uint8_t> blobFor(uint32_t node, uint8_t filler) {
  std::vector<uint8_t> b(8 + kBlobPayloadBytes, filler);
  std::memcpy(b.data(), "BLOB", 4);
  std::memcpy(b.data() + 4, &node, 4);
  return b;
}
inline std::vector<uint8_t> blobFor(uint32_t node) {
  return blobFor(node, uint8_t(node * 31));
}

// Every blob's occluder grid: 2 x 2 cells at 0 m (what the driver keeps while it is resident).
inline OccluderGrid blobOccluders() {
  OccluderGridBuilder builder({0, 0}, {2, 2}, 2);
  builder.addTriangle({0, 2, 0}, {0, 0, 2}, 0.0);
  return std::move(builder).finish();
}

class BlobKind final : public DrawnChunkKind<RecordedFrame> {
 public:
  explicit BlobKind(RecordingBackend& backend) : mBackend(backend) {}
  MeshKind meshKind() const override { return kBlobMeshKind; }
  Result<LoadedChunk> decode(const ChunkBlob& blob) const override {
    const auto mesh = blob.bytes.mesh();
    uint32_t node = 0;
    if (mesh.size() != 8 + kBlobPayloadBytes || std::memcmp(mesh.data(), "BLOB", 4) != 0)
      return makeError(blob.tilesetName, "chunk " + std::to_string(blob.node) + " is no blob");
    std::memcpy(&node, mesh.data() + 4, 4);
    if (node != blob.node)
      return makeError(blob.tilesetName, "chunk " + std::to_string(blob.node) + " is another's");
    auto payload = std::make_unique<BlobPayload>();
    payload->node = node;
    payload->filler = mesh[8];
    return LoadedChunk{std::move(payload), kBlobPayloadBytes, 0, blobOccluders()};
  }
  void beginFrame() override { mBackend.beginFrame(); }
  UploadRoom prepare(const ChunkPayload&) override { return UploadRoom::kReady; }
  uint64_t upload(uint32_t node, const ChunkPayload& payload) override {
    EXPECT_EQ(static_cast<const BlobPayload&>(payload).node, node);
    uploadedFiller[node] = static_cast<const BlobPayload&>(payload).filler;
    mBackend.upload(node);
    if (uploaded.insert(node).second) ++mGroupMembers[node / kGroup];
    return kBlobPayloadBytes;
  }
  void release(uint32_t node) override {
    mBackend.release(node);
    if (uploaded.erase(node) && --mGroupMembers[node / kGroup] == 0)
      mGroupMembers.erase(node / kGroup);
  }
  /// With `takesRecords`, an uploaded chunk takes a new record in place (kept here).
  bool updateRecord(uint32_t node, const NodeRecord& record) override {
    if (!takesRecords || !uploaded.count(node)) return false;
    recordsInPlace[node] = record;
    return true;
  }
  bool takesRecords = false;
  std::map<uint32_t, NodeRecord> recordsInPlace;
  /// Like super-chunk blocks: every group of kGroup consecutive nodes with a chunk uploaded
  /// holds `sharedPerGroup` bytes besides them.
  uint64_t sharedBytes() const override { return mGroupMembers.size() * sharedPerGroup; }
  static constexpr uint32_t kGroup = 4;
  uint64_t sharedPerGroup = 0;
  std::set<uint32_t> uploaded;
  std::map<uint32_t, uint8_t> uploadedFiller;  ///< per node: its last upload's
  void addDraws(RecordedFrame& frame, std::span<const SelectedChunk> chunks) override {
    frame.draws.insert(frame.draws.end(), chunks.begin(), chunks.end());
    mBackend.draw(chunks);
  }

 private:
  RecordingBackend& mBackend;
  std::map<uint32_t, uint32_t> mGroupMembers;  // per group with a chunk uploaded: how many
};

/// A FullTree of `levels` levels written as a tileset of blob chunks (mesh kind 7). The blob
/// of node `misfiled` (if any) is the next node's: its CRC is right, its decode fails.
inline std::string writeBlobTileset(const std::string& path, int levels,
                                    uint32_t misfiled = kNoNode) {
  FullTree full(levels);
  full.header.meshKind = kBlobMeshKind;
  auto writer = TilesetWriter::create(path);
  EXPECT_TRUE(writer.ok());
  for (uint32_t i = 0; i < full.nodes.size(); ++i) {
    const std::vector<uint8_t> blob = blobFor(i == misfiled ? i + 1 : i);
    NodeRecord& n = full.nodes[i];
    n.meshKind = kBlobMeshKind;
    n.blobOffset = (*writer)->appendBlob(blob).value();
    n.blobBytes = uint32_t(blob.size());
    n.blobCrc = crc32Of(blob);
  }
  EXPECT_TRUE((*writer)->finish(full.header, full.nodes, "{}").ok());
  return path;
}

}  // namespace terralod
