#include "terralod/render/terrain_scene.h"

namespace terralod {
namespace {

double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

Result<std::unique_ptr<TerrainScene>> TerrainScene::create(std::unique_ptr<TilesetReader> tileset) {
  for (const NodeRecord& n : tileset->nodes())
    if (n.meshKind != MeshKind::kStaticRtin)
      return makeError(tileset->name(), "chunk mesh kind " + std::to_string(int(n.meshKind)) +
                                            " is not supported by this renderer");
  auto renderer = TerrainRenderer::create();
  if (!renderer) return renderer.error();
  ChunkTree tree(tileset->header(), tileset->nodes());
  return std::unique_ptr<TerrainScene>(
      new TerrainScene(std::move(tileset), std::move(tree), std::move(renderer).value()));
}

TerrainScene::TerrainScene(std::unique_ptr<TilesetReader> tileset, ChunkTree tree,
                           TerrainRenderer renderer)
    : mTileset(std::move(tileset)), mTree(std::move(tree)), mRenderer(std::move(renderer)) {
  mSelected.reserve(mTree.nodes().size());
}

Result<FrameStats> TerrainScene::renderFrame(const View& view, const SelectionOptions& options,
                                             const TerrainStyle& style, bool reselect) {
  FrameStats stats;
  if (reselect) {
    const auto selectStart = std::chrono::steady_clock::now();
    mLastSelection = selectChunks(mTree, view, options, mSelected);
    stats.selectMicroseconds = secondsSince(selectStart) * 1e6;
  }
  stats.selection = mLastSelection;

  if (Status s = load(mSelected, stats); !s) return s.error();
  stats.draw = mRenderer.draw(view, mTree, mSelected, mStore, style);
  return stats;
}

Result<FrameStats> TerrainScene::drawChunks(const View& view, std::span<const SelectedChunk> chunks,
                                            const TerrainStyle& style) {
  FrameStats stats;
  if (Status s = load(chunks, stats); !s) return s.error();
  stats.draw = mRenderer.draw(view, mTree, chunks, mStore, style);
  return stats;
}

Status TerrainScene::load(std::span<const SelectedChunk> chunks, FrameStats& stats) {
  const auto loadStart = std::chrono::steady_clock::now();
  for (const SelectedChunk& s : chunks) {
    if (mStore.find(s.node)) continue;
    auto chunk = mTileset->readChunkData(s.node);
    if (!chunk) return chunk.error();
    if (mTileset->header().textured() &&
        (!chunk->texture || !chunk->texture->find(TextureLayerKind::kColor) ||
         !chunk->texture->find(TextureLayerKind::kNormal)))
      return makeError(mTileset->name(),
                       "chunk " + std::to_string(s.node) + " lacks its colour or normal texture");
    const auto uploadStart = std::chrono::steady_clock::now();
    mStore.upload(s.node, chunk->geometry, chunk->texture ? &*chunk->texture : nullptr);
    stats.uploadMilliseconds += secondsSince(uploadStart) * 1e3;
    ++stats.loads;
  }
  stats.loadMilliseconds = secondsSince(loadStart) * 1e3;
  return {};
}

}  // namespace terralod
