#pragma once
// One VIPM chunk on the GPU, with the CPU state that drives its level of detail: its vertices
// in its block's buffers (vipm_block.h: positions, re-uploaded over the geomorphing range,
// materials and splat weights), one index buffer of its own holding every part at a fixed
// place plus the flanges of the current border, and its stored normal map (a BC5 texture) and
// blot texture in its block's layer. Render thread only.

#include <array>
#include <cstdint>
#include <vector>

#include "gl_object.h"
#include "terralod/vipm/vipm_fans.h"
#include "vipm_block.h"
#include "vipm_payload.h"

namespace terralod {

class VipmGpuChunk {
 public:
  /// Uploads the chunk at its finest level into `slot` of `block` (which must fit its
  /// textures and outlive it) and makes its index buffer.
  VipmGpuChunk(const VipmChunkPayload& payload, VipmBlock& block, int slot);
  ~VipmGpuChunk();
  VipmGpuChunk(const VipmGpuChunk&) = delete;
  VipmGpuChunk& operator=(const VipmGpuChunk&) = delete;

  /// Moves to the level for allowed error `theta` (metres): applies or undoes collapses,
  /// geomorphs the vertices in the window, and uploads what changed.
  void update(double theta, Geomorph geomorph) { update(theta, theta, geomorph); }
  /// The collapses `theta` chooses, geomorphed as `morphTheta` says (bench: an earlier frame's
  /// level geomorphed for this frame).
  void update(double theta, double morphTheta, Geomorph geomorph);
  /// Hangs the flanges `depth` metres below their tops (an edit moved the node's flange
  /// depth, not its mesh), uploading the flange vertices.
  void setFlangeDepth(float depth);

  struct Range {
    int material = kWholeChunk;
    uint32_t firstIndex = 0;
    uint32_t count = 0;  ///< indices drawn now (its fans included)
  };
  /// The whole chunk first, then one per material present.
  const std::vector<Range>& parts() const { return mRanges; }
  Range flanges() const { return {kWholeChunk, mFlangeFirst, uint32_t(mFlangeIndices.size())}; }
  /// Stitching by fans (vipm_fans.h), after every drawn chunk's update of the frame: adds this
  /// chunk's drawn border points to the frame's table, then replaces its border triangles by
  /// fans onto the table's points (`table` null: no fans, the chunk's own triangles). Uploads
  /// only what changed: the replaced triangles, the fans and their inserted points.
  void addStitchPoints(StitchTable& table) const;
  /// Returns whether its fans changed.
  bool stitch(const StitchTable* table);
  /// Fan triangles drawn now, and the triangles they replace.
  uint32_t fanTriangles() const { return uint32_t(mFans.triangles.size()); }
  uint32_t replacedTriangles() const { return uint32_t(mFans.replaced.size()); }
  /// Its south-west grid point.
  int64_t cornerX() const { return mStitcher.chunk().cornerX; }
  int64_t cornerY() const { return mStitcher.chunk().cornerY; }
  /// Collapses applied now.
  uint32_t applied() const { return mLevels.applied(); }
  /// Vertices of the mesh active now (flanges left out).
  uint32_t activeVertices() const { return mLevels.activeVertices(); }
  /// Its block, holding per vertex its position, its own material (one byte) and its splat
  /// weights as drawn now, one unsigned normalised byte per material (8 bytes; its own
  /// material alone, except while a blot root's vertex geomorphs: a root's collapses join
  /// different materials, so a corner's material changes only by fading,
  /// morphMaterialWeights); its normal map and its blot texture (encoded colours,
  /// vipm_blot.h; mips, laid out as the normal map) are layer slot() of its arrays.
  const VipmBlock& block() const { return mBlock; }
  VipmBlock& block() { return mBlock; }
  int slot() const { return mSlot; }
  /// Its vertices in the block's buffers: the mesh's, the flange copies, then room for the
  /// fans' inserted points.
  VipmVertexRange vertices() const { return mVertices; }
  uint32_t indexBuffer() const { return mIndexBuffer.id(); }
  /// What its whole part draws now, as indices into the block's buffers: its triangles (the
  /// fans' replaced ones left out) and fans to `surface`, with `flanges` its flanges to
  /// `flanges`.
  void appendDrawn(std::vector<uint32_t>& surface, std::vector<uint32_t>* flanges) const;
  /// Changes whenever what appendDrawn gives may have changed.
  uint64_t indexVersion() const { return mIndexVersion; }
  /// Different for every chunk made (a new chunk may take a released one's address).
  uint64_t serial() const { return mSerial; }
  /// Texels a side of the normal map (vipmNormalMapCells(cells) + 1).
  uint32_t normalSize() const { return mNormalSize; }
  /// The node's side in cells (unclipped).
  uint32_t cells() const { return mCells; }
  /// Grid cells between the normal map's texels: 1 up to a root, more above.
  uint32_t texelCells() const { return mCells / std::max(mNormalSize - 1, 1u); }
  int32_t width() const { return mWidth; }
  int32_t height() const { return mHeight; }
  double zBase() const { return mZBase; }
  /// GPU bytes plus the CPU state kept for level changes.
  uint64_t bytes() const { return mBytes; }
  /// GPU bytes alone.
  uint64_t gpuBytes() const { return mGpuBytes; }
  /// Of those, the part in its block (its vertices and its texture layers).
  uint64_t blockBytes() const { return mBlockBytes; }

 private:
  void uploadPositions(uint32_t first, uint32_t count);
  void writeIndices(uint32_t first, std::span<const uint16_t> indices);
  // Sets the weights of the window's vertices (their own material alone outside it) and the
  // bytes uploaded of vertices [first, end) (both windows') and of the flange copies.
  void morphMaterials(const MorphWindow& previous, const MorphWindow& window, double morphTheta,
                      uint32_t first, uint32_t end);
  // Own material alone.
  MaterialWeights ownWeights(uint32_t v) const;

  // Part i's triangles of the whole part's `replaced`, as slots of part i.
  void partSlots(size_t i, std::span<const uint32_t> replaced, std::vector<uint32_t>& out) const;
  bool fanInPart(const std::array<uint32_t, 3>& triangle, int material) const;

  ProgressiveMesh mMesh;
  VipmLevels mLevels;
  VipmStitcher mStitcher;
  StitchFans mFans;                              // drawn now
  std::vector<std::vector<uint32_t>> mReplaced;  // per part: its slots degenerate on the GPU
  std::vector<uint32_t> mFanOffset;              // per part: where its fans start (indices)
  std::vector<std::vector<uint16_t>> mPartFans;  // per part: its fans' indices, uploaded
  std::vector<uint8_t> mPrefixUploaded;          // per part: its prefix re-uploaded this frame
  uint32_t mFanVertexFirst = 0;                  // the inserted points' first vertex
  uint64_t mFanSignature = 0;  // VipmStitcher::signature of what mFans was made from
  bool mFanSignatureValid = false;
  std::vector<std::array<float, 3>> mOwn;    // own positions (flange vertices after the mesh's)
  std::vector<std::array<float, 3>> mDrawn;  // drawn now (geomorphed)
  std::vector<uint8_t> mMaterials;           // own, per vertex (flanges too)
  std::vector<MaterialWeights> mWeights;     // per mesh vertex as drawn now (kToTarget only)
  std::vector<std::array<uint8_t, kMaxMaterials>> mWeightBytes;  // as uploaded (flanges too)
  MaterialFade mFade = MaterialFade::kKeep;  // kKeep: every vertex its own material alone
  Flanges mFlanges;
  float mFlangeDepth = 0.0f;
  MorphWindow mWindow;
  bool mFlangesValid = false;
  std::vector<uint16_t> mFlangeIndices;
  std::vector<Range> mRanges;
  uint32_t mFlangeFirst = 0;
  uint32_t mNormalSize = 0;
  uint32_t mCells = 0;
  int32_t mWidth = 0, mHeight = 0;
  double mZBase = 0.0;
  VipmBlock& mBlock;
  int mSlot = 0;
  VipmVertexRange mVertices;
  GlBuffer mIndexBuffer;
  uint64_t mIndexVersion = 0;
  uint64_t mSerial = 0;
  uint64_t mBytes = 0, mGpuBytes = 0, mBlockBytes = 0;
};

}  // namespace terralod
