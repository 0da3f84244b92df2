#include "terralod/render/static_chunk_kind.h"

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

StaticChunkKind::StaticChunkKind(GpuChunkStore& store, TerrainRenderer& renderer,
                                 ChunkTextures textures)
    : mStore(store), mRenderer(renderer), mTextures(textures) {}

Result<LoadedChunk> StaticChunkKind::decode(const ChunkBlob& blob) const {
  auto data =
      decodeStaticChunk(blob.bytes, blob.tilesetName + " chunk " + std::to_string(blob.node));
  if (!data) return data.error();
  if (mTextures == ChunkTextures::kRequired &&
      (!data->texture || !data->texture->find(TextureLayerKind::kColor) ||
       !data->texture->find(TextureLayerKind::kNormal)))
    return makeError(blob.tilesetName,
                     "chunk " + std::to_string(blob.node) + " lacks its colour or normal texture");
  auto payload = std::make_unique<StaticChunkPayload>();
  payload->data = std::move(data).value();
  LoadedChunk loaded;
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
  frame.stats = mRenderer.draw(frame.view, frame.tree, chunks, mStore, frame.style);
}

}  // namespace terralod
