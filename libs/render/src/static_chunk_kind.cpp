#include "terralod/render/static_chunk_kind.h"

#include <algorithm>
#include <limits>

#include "terralod/format/chunk_position.h"
#include "terralod/format/static_chunk.h"

namespace terralod {
namespace {

// A static RTIN chunk as the loaders decode it.
struct StaticChunkPayload final : ChunkPayload {
  ChunkData data;
};

// The one downcast: the driver hands this kind only payloads its decode() made.
const ChunkData& dataOf(const ChunkPayload& payload) {
  return static_cast<const StaticChunkPayload&>(payload).data;
}

uint64_t decodedBytes(const ChunkData& d) {
  uint64_t bytes = 0;
  for (const ChunkPart& p : d.geometry.parts)
    bytes += p.vertices.size() * sizeof(ChunkVertex) + p.indices.size() * sizeof(uint32_t);
  if (d.texture) bytes += d.texture->bytes();
  return bytes;
}

}  // namespace

OccluderGrid staticChunkOccluders(const ChunkGeometry& geometry) {
  std::array<uint32_t, 2> lo{UINT32_MAX, UINT32_MAX}, hi{0, 0};
  for (const ChunkPart& p : geometry.parts)
    for (uint32_t k = 0; k < p.surfaceIndexCount; ++k) {
      const ChunkVertex& v = p.vertices[p.indices[k]];
      lo = {std::min<uint32_t>(lo[0], v.x), std::min<uint32_t>(lo[1], v.y)};
      hi = {std::max<uint32_t>(hi[0], v.x), std::max<uint32_t>(hi[1], v.y)};
    }
  OccluderGridBuilder builder(lo, hi);
  for (const ChunkPart& p : geometry.parts)
    for (uint32_t k = 0; k + 2 < p.surfaceIndexCount; k += 3) {
      std::array<uint32_t, 3> xs, ys;
      double lowest = std::numeric_limits<double>::infinity();
      for (int j = 0; j < 3; ++j) {
        const ChunkVertex& v = p.vertices[p.indices[k + uint32_t(j)]];
        xs[size_t(j)] = v.x;
        ys[size_t(j)] = v.y;
        lowest = std::min(
            {lowest, chunkVertexHeight(geometry, v, 0.0), chunkVertexHeight(geometry, v, 1.0)});
      }
      builder.addTriangle(xs, ys, lowest);
    }
  return std::move(builder).finish();
}

StaticChunkKind::StaticChunkKind(GpuChunkStore& store, TerrainRenderer& renderer,
                                 ChunkTextures textures, HorizonCulling culling)
    : mStore(store), mRenderer(renderer), mCulling(culling), mTextures(textures) {}

Result<LoadedChunk> StaticChunkKind::decode(const ChunkBlob& blob) const {
  auto data =
      decodeStaticChunk(blob.bytes, blob.tilesetName + " chunk " + std::to_string(blob.node));
  if (!data) return data.error();
  // A chunk that inherits its texture draws its ancestor's (TerrainPass): it has none.
  if (mTextures == ChunkTextures::kRequired && !blob.record.inheritsTexture() &&
      (!data->texture || !data->texture->colourSource() ||
       !data->texture->find(TextureLayerKind::kNormal)))
    return makeError(blob.tilesetName,
                     "chunk " + std::to_string(blob.node) + " lacks its colour or normal texture");
  auto payload = std::make_unique<StaticChunkPayload>();
  payload->data = std::move(data).value();
  LoadedChunk loaded;
  if (mCulling == HorizonCulling::kOn)
    loaded.occluders = staticChunkOccluders(payload->data.geometry);
  loaded.bytes = decodedBytes(payload->data);
  loaded.bytesRead = payload->data.bytesRead;
  loaded.payload = std::move(payload);
  return loaded;
}

void StaticChunkKind::beginFrame() {
  mStore.poll();
}

UploadRoom StaticChunkKind::prepare(const ChunkPayload& payload) {
  const ChunkData& data = dataOf(payload);
  return mStore.reserve(data.geometry, data.texture ? &*data.texture : nullptr)
             ? UploadRoom::kReady
             : UploadRoom::kMemoryOnItsWay;
}

uint64_t StaticChunkKind::upload(uint32_t node, const ChunkPayload& payload) {
  const ChunkData& data = dataOf(payload);
  mStore.upload(node, data.geometry, data.texture ? &*data.texture : nullptr);
  return mStore.find(node)->bytes;
}

void StaticChunkKind::release(uint32_t node) {
  mStore.release(node);
}

void StaticChunkKind::addDraws(TerrainFrame& frame, std::span<const SelectedChunk> chunks) {
  mRenderer.drawStaticChunks(frame.context, frame.tree, chunks, mStore, frame.stats);
}

}  // namespace terralod
