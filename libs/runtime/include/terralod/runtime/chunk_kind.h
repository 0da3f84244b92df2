#pragma once
// A chunk kind: how the chunks of one MeshKind are decoded, put on the GPU (or wherever a
// backend keeps them), freed and drawn. Static RTIN chunks are one kind (libs/render,
// StaticChunkKind); tests register others. The frame driver (frame_driver.h) dispatches on
// each node's MeshKind; a tileset using a kind nobody registered is refused when the driver
// is made ("no kind registered for mesh kind N").
//
// Thread contract:
//   - decode() runs on loader threads (the TaskRunner's), several at once for different
//     nodes, and on the render thread for the roots before the first frame. It must be
//     thread-safe, must not touch GL or anything the render thread changes, and returns the
//     chunk as a ChunkPayload of its own with the memory it holds.
//   - beginFrame(), prepare(), upload(), release() and addDraws() run on the render thread
//     only, in this order within a frame: beginFrame once; per ready chunk prepare, then
//     upload when prepare said kReady; release for evicted chunks; addDraws when the frame is
//     drawn. A payload given to prepare() and upload() is always one this kind's decode()
//     made, for the same node (so a kind may downcast it to its own payload type).
//   - A kind outlives every driver it is registered with.

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "terralod/core/result.h"
#include "terralod/format/node_bytes.h"
#include "terralod/format/tileset_format.h"
#include "terralod/runtime/chunk_tree.h"
#include "terralod/runtime/residency.h"
#include "terralod/runtime/selection.h"

namespace terralod {

/// What a loader hands a kind to decode.
struct ChunkBlob {
  uint32_t node = 0;
  const NodeBytes& bytes;          ///< read and mesh-CRC-checked by the TilesetReader
  const std::string& tilesetName;  ///< for errors: "<tileset>: chunk N ..."
  /// The node's record as it stands: the file's, or an edit's (FrameDriver::replaceNodes).
  const NodeRecord& record;
};

/// Whether a ready chunk can be uploaded now.
enum class UploadRoom : uint8_t {
  kReady,          ///< upload() may run now
  kMemoryOnItsWay  ///< its GPU memory is being made: give it back, try in a later frame
};

class ChunkKind {
 public:
  virtual ~ChunkKind() = default;
  virtual MeshKind meshKind() const = 0;

  /// Loader thread (see the contract above). LoadedChunk::bytes: memory the payload holds;
  /// the driver fills in bytesRead.
  virtual Result<LoadedChunk> decode(const ChunkBlob& blob) const = 0;

  // --- render thread ---
  /// Once per frame before uploads (e.g. adopt memory made ahead on a worker).
  virtual void beginFrame() {}
  /// Reserves what upload() needs, or says it is not there yet.
  virtual UploadRoom prepare(const ChunkPayload& payload) = 0;
  /// Puts a decoded chunk in place under `node`; returns the bytes it takes there.
  virtual uint64_t upload(uint32_t node, const ChunkPayload& payload) = 0;
  /// Frees what upload() made for `node`.
  virtual void release(uint32_t node) = 0;
  /// An edit changed the record of uploaded `node` but not its bytes: takes the new record
  /// in place and returns true, or returns false and the driver decodes the chunk again.
  virtual bool updateRecord(uint32_t /*node*/, const NodeRecord& /*record*/) { return false; }
  /// Memory the kind holds besides what upload() returned for its chunks: storage several
  /// chunks share, with its room to spare. Counted against the budget with them.
  virtual uint64_t sharedBytes() const { return 0; }
};

/// A kind that draws into a renderer's frame of type `Frame` (libs/render: TerrainFrame;
/// tests: a recording frame). Render thread: adds the draws of `chunks` (all of this kind,
/// in selection order, with their morph parameters) to `frame`.
template <class Frame>
class DrawnChunkKind : public ChunkKind {
 public:
  virtual void addDraws(Frame& frame, std::span<const SelectedChunk> chunks) = 0;
};

/// The kinds a driver knows, by MeshKind. Holds pointers: the kinds outlive it.
class ChunkKinds {
 public:
  /// Registers `kind` for its MeshKind (replacing an earlier one for the same MeshKind).
  void add(ChunkKind& kind);
  const ChunkKind* find(MeshKind kind) const;
  ChunkKind* find(MeshKind kind);
  /// Every registered kind, in registration order.
  std::span<ChunkKind* const> all() const { return mKinds; }
  /// Every node's kind is registered; otherwise "<name>: no kind registered for mesh kind N".
  Status covers(const ChunkTree& tree, const std::string& name) const;

 private:
  std::vector<ChunkKind*> mKinds;
};

/// A selection split into runs of one mesh kind each (for each kind's addDraws). A selection
/// of one kind is one run over it (no copy); a mixed one is grouped by kind, each group in
/// selection order.
class KindRuns {
 public:
  struct Run {
    MeshKind kind;
    std::span<const SelectedChunk> chunks;
  };
  void split(const ChunkTree& tree, std::span<const SelectedChunk> chunks);
  std::span<const Run> runs() const { return mRuns; }

 private:
  std::vector<SelectedChunk> mGrouped;
  std::vector<Run> mRuns;
};

}  // namespace terralod
