#pragma once
// VIPM chunks (MeshKind::kVipm; docs/format.md "VIPM tilesets") as a chunk kind
// (terralod/runtime/chunk_kind.h, whose thread contract applies). Loader threads decode a blob,
// reconstruct its index parts (libs/vipm), compute its normal map from the stored heights and
// its flanges. The render thread uploads it (its own buffers and normal map per chunk) and,
// each frame, moves every drawn chunk to the level its allowed error θ asks for
// (vipm_theta.h: τ·D/K with D the selection's box distance, raised while a late split eases in),
// geomorphs the collapses in the window (none with morphing off: `--no-morph` shows the pops),
// re-uploads what changed, and draws it by texture splatting (one pass per material).
//
// Horizon culling: the kind makes no occluder grids; the driver then uses each chunk's box
// solid under minZ, which lies under every level it can draw.

#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <span>
#include <tuple>
#include <unordered_map>
#include <vector>

#include "terralod/core/result.h"
#include "terralod/format/tileset_reader.h"
#include "terralod/render/terrain_frame.h"
#include "terralod/runtime/chunk_kind.h"
#include "terralod/runtime/chunk_tree.h"
#include "terralod/runtime/selection.h"
#include "terralod/runtime/view.h"

namespace terralod {

/// θ (metres) the VIPM kind draws `chunk` with in `view` under screen-space bound `tau`:
/// vipmTheta of τ·D/K, D the selection's eye-to-box distance, and the chunk's morph parameter.
/// The kind draws with it and the bench (libs/measure) measures what it drew with it.
double vipmDrawnTheta(const ChunkTree& tree, const View& view, double tau,
                      const SelectedChunk& chunk);

/// A VIPM chunk drawn at given allowed errors (metres), e.g. as it was drawn in an earlier
/// frame: bench's material pops draw two frames' states from one camera.
struct VipmChunkAt {
  uint32_t node = 0;
  double theta = 0.0;       ///< chooses the applied and geomorphing collapses
  double morphTheta = 0.0;  ///< where the geomorph stands (as drawn: theta)
};

/// The material of a pixel of a material-ID image (VipmChunkKind::addMaterialIdDraws): the
/// material index with the largest splat weight there, or -1 where no terrain was drawn.
/// `red`: the pixel's red channel.
inline int vipmMaterialOfPixel(uint8_t red) {
  return red < 8 ? -1 : int(red & 7u);
}

class VipmPass;
class StitchTable;
class VipmGpuChunk;
class VipmBlock;
struct VipmDraw;

class VipmChunkKind final : public DrawnChunkKind<TerrainFrame> {
 public:
  /// Compiles the splatting program and makes the materials' detail textures (a GlContext
  /// must be current). `tileset` must outlive the kind.
  static Result<std::unique_ptr<VipmChunkKind>> create(const TilesetReader& tileset);
  ~VipmChunkKind() override;

  MeshKind meshKind() const override { return MeshKind::kVipm; }
  Result<LoadedChunk> decode(const ChunkBlob& blob) const override;
  UploadRoom prepare(const ChunkPayload&) override { return UploadRoom::kReady; }
  uint64_t upload(uint32_t node, const ChunkPayload& payload) override;
  void release(uint32_t node) override;
  /// A new flange depth hangs the chunk's flanges again (its mesh is the same).
  bool updateRecord(uint32_t node, const NodeRecord& record) override;
  void addDraws(TerrainFrame& frame, std::span<const SelectedChunk> chunks) override;

  /// Draws `chunks`, each at its own θ (geomorphed at its morphTheta when frame.selection.morph
  /// is on), into the frame as a material-ID image (vipmMaterialOfPixel reads it; the frame
  /// should be cleared to black without sky). Chunks not uploaded are counted in
  /// frame.stats.missing. Leaves the chunks at those levels: the next addDraws moves them.
  void addMaterialIdDraws(TerrainFrame& frame, std::span<const VipmChunkAt> chunks);

  /// The collapses applied now in `node` (for tests); none when it is not uploaded.
  uint32_t appliedCollapses(uint32_t node) const;
  /// Milliseconds each chunk decoded since the last call took to decode and reconstruct (on
  /// the loader threads), in no particular order; the list is then emptied.
  std::vector<double> takeReconstructMs();
  /// Fan stitching's CPU time per frame drawn with fans (render thread): each chunk whose fans
  /// changed (a level change of it or a neighbour, or a border vertex geomorphing), and the
  /// whole frame's (the drawn border points gathered too), in milliseconds; the list is then
  /// emptied.
  struct FanTiming {
    std::vector<double> changedMs;
    double totalMs = 0.0;
  };
  std::vector<FanTiming> takeFanTimings();
  /// GPU memory the uploaded chunks take.
  uint64_t gpuBytes() const { return mGpuBytes; }
  /// GPU memory the super-chunk blocks hold beyond their chunks' own: spare vertex room and
  /// texture layers no chunk uses (counted in the budget as sharedBytes).
  uint64_t blockSpareBytes() const;
  uint64_t sharedBytes() const override { return blockSpareBytes(); }

 private:
  VipmChunkKind(const TilesetReader& tileset, std::unique_ptr<VipmPass> pass);

  // A super-chunk's storage: the cells of its level's chunks and its place in the grid of
  // 4 × 4 blocks of them.
  using BlockKey = std::tuple<uint32_t, int64_t, int64_t>;
  static BlockKey blockKey(int64_t cornerX, int64_t cornerY, uint32_t cells);

  const TilesetReader& mTileset;
  std::unique_ptr<VipmPass> mPass;
  std::map<BlockKey, std::unique_ptr<VipmBlock>> mBlocks;  // before the chunks: they use them
  std::unordered_map<uint32_t, std::unique_ptr<VipmGpuChunk>> mChunks;
  uint64_t mGpuBytes = 0;
  uint64_t mBlockBytesUsed = 0;  // the uploaded chunks' share of their blocks
  // Fans or no fans for every drawn chunk, after their levels are set.
  void stitch(const TerrainStyle& style, std::span<const VipmDraw> draws);
  std::vector<VipmDraw> mDraws;               // per frame, kept to avoid allocating
  std::unique_ptr<StitchTable> mStitchTable;  // per frame
  std::vector<FanTiming> mFanTimings;
  mutable std::mutex mTimingMutex;
  mutable std::vector<double> mReconstructMs;  // guarded by mTimingMutex
};

}  // namespace terralod
