#pragma once
// Static RTIN chunks (MeshKind::kStaticRtin) as a chunk kind (terralod/runtime/chunk_kind.h,
// whose thread contract applies): decoded on loader threads by the format's
// decodeStaticChunk into ChunkData, put into a GpuChunkStore on the render thread, drawn in the
// frame's opaque terrain pass (TerrainRenderer::drawStaticChunks).

#include "terralod/format/chunk_codec.h"
#include "terralod/render/gpu_chunk_store.h"
#include "terralod/render/terrain_frame.h"
#include "terralod/render/terrain_renderer.h"
#include "terralod/runtime/chunk_kind.h"
#include "terralod/runtime/horizon_culling.h"
#include "terralod/runtime/occluder_grid.h"

namespace terralod {

/// A static chunk's occluder grid (occluder_grid.h), as its decode makes it: the footprint
/// is its surface vertices' extent; each surface triangle lowers the cells its bounding box
/// touches to the least of its corners' heights at morph 0 and 1 (the drawn height is linear
/// in the morph parameter, and over a triangle linear between its corners).
OccluderGrid staticChunkOccluders(const ChunkGeometry& geometry);

/// Whether a tileset's static chunks must carry colour and normal textures.
enum class ChunkTextures : uint8_t { kOptional, kRequired };

class StaticChunkKind final : public DrawnChunkKind<TerrainFrame> {
 public:
  /// `store` and `renderer` must outlive the kind. With horizon culling off, decode makes no
  /// occluder grids (nothing would read them, and they would take from the budget).
  StaticChunkKind(GpuChunkStore& store, TerrainRenderer& renderer, ChunkTextures textures,
                  HorizonCulling culling = HorizonCulling::kOn);

  MeshKind meshKind() const override { return MeshKind::kStaticRtin; }
  Result<LoadedChunk> decode(const ChunkBlob& blob) const override;
  void beginFrame() override;
  UploadRoom prepare(const ChunkPayload& payload) override;
  uint64_t upload(uint32_t node, const ChunkPayload& payload) override;
  void release(uint32_t node) override;
  void addDraws(TerrainFrame& frame, std::span<const SelectedChunk> chunks) override;

 private:
  GpuChunkStore& mStore;
  TerrainRenderer& mRenderer;
  HorizonCulling mCulling;
  ChunkTextures mTextures;
};

}  // namespace terralod
