#include "terralod/build/chunk_pass.h"

#include <algorithm>
#include <atomic>
#include <bit>
#include <cassert>
#include <cmath>
#include <functional>
#include <limits>
#include <mutex>
#include <optional>
#include <unordered_map>

#include "terralod/build/chunk_encoder.h"
#include "terralod/build/chunk_mesher.h"
#include "terralod/build/tile_pyramid.h"
#include "terralod/core/parallel.h"

namespace terralod {
namespace {

float floatBelow(double v) {
  const float f = static_cast<float>(v);
  return double(f) <= v ? f : std::nextafter(f, -std::numeric_limits<float>::infinity());
}
float floatAbove(double v) {
  const float f = static_cast<float>(v);
  return double(f) >= v ? f : std::nextafter(f, std::numeric_limits<float>::infinity());
}

// Heights of one block's window (its margin excepted); anything outside it is a bug in the
// caller.
class WindowSampler final : public HeightSampler {
 public:
  explicit WindowSampler(const BlockWindow& window) : mWindow(window) {}
  double at(int32_t x, int32_t y) const override {
    const int32_t lx = x - mWindow.x0, ly = y - mWindow.y0;
    if (lx < 0 || ly < 0 || lx > mWindow.cells || ly > mWindow.cells) return std::nan("");
    return mWindow.at(x, y);
  }

 private:
  const BlockWindow& mWindow;
};

// The texture pass's reads: the block window with its margin, which the chunk pass has read
// already, from it; anything else from `next`.
class BlockWindowReads final : public HeightWindows {
 public:
  BlockWindowReads(const BlockWindow* window, HeightWindows& next) : mWindow(window), mNext(next) {}
  Status read(int32_t x0, int32_t y0, int32_t w, int32_t h, float* out, unsigned worker) override {
    const BlockWindow* b = mWindow;
    if (b && x0 == b->x0 - b->margin && y0 == b->y0 - b->margin && w == b->stride() &&
        h == b->stride()) {
      std::copy(b->values.begin(), b->values.end(), out);
      return {};
    }
    return mNext.read(x0, y0, w, h, out, worker);
  }

 private:
  const BlockWindow* mWindow;
  HeightWindows& mNext;
};

// Reads a texture pass must not make: all it needs is in the window it was given.
class NoOtherReads final : public HeightWindows {
 public:
  Status read(int32_t, int32_t, int32_t, int32_t, float*, unsigned) override {
    return Error{"internal error: the texture pass read outside its block's window"};
  }
};

}  // namespace

namespace {

// A built chunk's blob, with its statistics filled into `node`.
Result<std::vector<uint8_t>> encodeChunk(const ChunkMesh& mesh, const ErrorBudget& budget,
                                         NodeRecord& node, int compressionLevel,
                                         ChunkPayloadVersion payload) {
  for (const MeshVertex& v : mesh.vertices)
    if (!std::isfinite(v.z) || !std::isfinite(v.morphTarget))
      return Error{"internal error: chunk " + std::to_string(node.level) + "/" +
                   std::to_string(node.x) + "/" + std::to_string(node.y) +
                   " has a vertex without a height"};
  auto encoded = encodeChunkMesh(mesh, budget, payload, compressionLevel);
  if (!encoded) return encoded.error();
  const ChunkGeometry* geometry = &encoded->geometry;
  std::vector<uint8_t> blob = std::move(encoded->blob);
  // Quantisation moves a drawn height (own or morphed) by up to half a step either way.
  const double halfStep = 0.5 * geometry->zStep;
  node.minZ = floatBelow(mesh.minZ - halfStep);
  node.maxZ = floatAbove(mesh.maxZ + halfStep);
  node.vertexCount = mesh.surfaceVertexCount;
  node.triangleCount = uint32_t(mesh.surfaceIndices.size() / 3);
  node.skirtTriangleCount = uint32_t(mesh.skirtIndices.size() / 3);
  // The skirts as drawn: whole steps below the rounded tops, at least the depth asked for.
  const uint16_t steps =
      *std::max_element(geometry->skirtSteps.begin(), geometry->skirtSteps.end());
  node.maxSkirtDepth = floatAbove(steps * geometry->zStep);
  node.blobBytes = uint32_t(blob.size());
  node.blobCrc = crc32Of(blob);
  return blob;
}

}  // namespace

Result<std::vector<uint8_t>> buildChunk(ChunkMesher& mesher, const ErrorBudget& budget,
                                        NodeRecord& node, int compressionLevel,
                                        ChunkPayloadVersion payload) {
  return encodeChunk(mesher.build(node.level, int32_t(node.x), int32_t(node.y)), budget, node,
                     compressionLevel, payload);
}

std::vector<NodeRecord> enumerateNodes(const TreeLayout& layout) {
  // Sized once: every stage of a staged build enumerates the whole tree (1.4 M nodes at
  // 65537²), and growing the vector touched up to twice its memory, all of it fresh.
  size_t count = 0;
  for (int32_t level = 0; level <= layout.depth; ++level)
    count += size_t(layout.chunksX(level)) * size_t(layout.chunksY(level));
  std::vector<NodeRecord> nodes;
  nodes.reserve(count);
  for (int32_t y = 0; y < layout.rootsY; ++y)
    for (int32_t x = 0; x < layout.rootsX; ++x) {
      NodeRecord n;
      n.x = uint32_t(x);
      n.y = uint32_t(y);
      nodes.push_back(n);
    }
  for (size_t i = 0; i < nodes.size(); ++i) {
    if (nodes[i].level == layout.depth) continue;
    const int32_t level = nodes[i].level + 1;
    for (int q = 0; q < 4; ++q) {
      const int32_t cx = int32_t(nodes[i].x) * 2 + (q & 1), cy = int32_t(nodes[i].y) * 2 + (q >> 1);
      if (!layout.chunkExists(level, cx, cy)) continue;
      if (nodes[i].childMask == 0) nodes[i].firstChild = uint32_t(nodes.size());
      nodes[i].childMask |= uint8_t(1u << q);
      NodeRecord c;
      c.level = uint8_t(level);
      c.x = uint32_t(cx);
      c.y = uint32_t(cy);
      c.parent = uint32_t(i);
      nodes.push_back(c);
    }
  }
  return nodes;
}

int32_t blockLevelOf(const TreeLayout& layout, int32_t blockCells) {
  const int32_t block = std::clamp(blockCells, layout.leafCells, layout.rootCells);
  return std::countr_zero(uint32_t(layout.rootCells / block));
}

int32_t firstGreedyLevel(int32_t blockLevel, CoarseHeights heights) {
  return heights == CoarseHeights::kEvery ? 0 : blockLevel + 1;
}

std::vector<uint32_t> blockNodesOf(const std::vector<NodeRecord>& nodes, int32_t blockLevel) {
  std::vector<uint32_t> out;
  for (uint32_t i = 0; i < nodes.size(); ++i)
    if (nodes[i].level == blockLevel) out.push_back(i);
  return out;
}

std::vector<uint32_t> coarseNodesOf(const std::vector<NodeRecord>& nodes, int32_t blockLevel) {
  std::vector<uint32_t> out;
  for (uint32_t i = 0; i < nodes.size(); ++i)
    if (nodes[i].level <= blockLevel) out.push_back(i);
  return out;
}

std::vector<uint32_t> chunksBelow(const std::vector<NodeRecord>& nodes, uint32_t blockNode) {
  std::vector<uint32_t> order;
  auto pushChildren = [&](uint32_t i) {
    const NodeRecord& n = nodes[i];
    for (uint32_t c = 0; c < uint32_t(std::popcount(unsigned(n.childMask))); ++c)
      order.push_back(n.firstChild + c);
  };
  pushChildren(blockNode);
  for (size_t k = 0; k < order.size(); ++k) pushChildren(order[k]);
  return order;
}

Result<ChunkTiles> blockTexturesFrom(
    TexturePass& textures, uint32_t blockNode, const BlockWindow& window, unsigned worker,
    std::vector<std::pair<uint32_t, std::vector<uint8_t>>>& blobs) {
  NoOtherReads none;
  BlockWindowReads reads(&window, none);
  return textures.buildBlock(blockNode, reads, worker, blobs);
}

Status readBlockWindow(const ChunkPassContext& context, HeightWindows& windows, int32_t x0,
                       int32_t y0, int32_t cells, BlockWindow& window, unsigned worker) {
  window.x0 = x0;
  window.y0 = y0;
  window.cells = cells;
  window.margin = context.textures ? BlockTexels::kMargin : 0;
  window.values.resize(size_t(window.stride()) * size_t(window.stride()));
  return windows.read(x0 - window.margin, y0 - window.margin, window.stride(), window.stride(),
                      window.values.data(), worker);
}

Result<BlockChunks> buildBlockChunks(const ChunkPassContext& context, uint32_t blockNode,
                                     const BlockWindow* window, ChunkMesher& mesher,
                                     const ActivationGrid& grid, HeightWindows& windows,
                                     unsigned worker) {
  const TreeLayout& layout = context.layout;
  std::vector<NodeRecord>& nodes = context.nodes;
  const int32_t block = std::clamp(context.blockCells, layout.leafCells, layout.rootCells);
  const NodeRecord& b = nodes[blockNode];
  const int32_t x0 = int32_t(b.x) * block, y0 = int32_t(b.y) * block;
  std::optional<WindowSampler> sampler;
  if (window) {
    assert(window->x0 == x0 && window->y0 == y0 && window->cells == block);
    sampler.emplace(*window);
    mesher.setHeights(*sampler);
  }
  mesher.setMethod(context.mesher, context.firstGreedyLevel);
  BlockChunks out;
  for (const uint32_t i : chunksBelow(nodes, blockNode)) {
    auto blob =
        buildChunk(mesher, context.budget, nodes[i], context.compressionLevel, context.payload);
    if (!blob) return blob.error();
    out.chunks.push_back({i, std::move(blob).value(), {}});
  }
  if (context.textures) {
    std::vector<std::pair<uint32_t, std::vector<uint8_t>>> textures;
    BlockWindowReads reads(window, windows);
    auto tiles = context.textures->buildBlock(blockNode, reads, worker, textures);
    if (!tiles) return tiles.error();
    out.tiles = std::move(tiles).value();
    std::unordered_map<uint32_t, size_t> where;
    for (size_t k = 0; k < out.chunks.size(); ++k) where.emplace(out.chunks[k].node, k);
    for (auto& [node, blob] : textures) {
      if (node == blockNode)
        out.blockTexture = std::move(blob);
      else
        out.chunks[where.at(node)].texture = std::move(blob);
    }
  }
  if (window) {
    // Vertices the block-level and coarser chunks will need, for after the window is gone.
    const uint8_t coarse = context.budget.activationForLevel(blockLevelOf(layout, block));
    const int32_t x1 = std::min(x0 + block, layout.cellsX),
                  y1 = std::min(y0 + block, layout.cellsY);
    for (int32_t y = y0; y <= y1; ++y)
      for (int32_t x = x0; x <= x1; ++x)
        if (grid.get(x, y) >= coarse)
          out.points.emplace_back(SparseHeights::key(x, y), window->at(x, y));
  }
  return out;
}

namespace {

// Chunks coarseNodes[begin, end) into out[k], in parallel, one mesher per thread; their
// surfaces into (*surfaces)[k] when asked.
Status buildChunkRange(const ChunkPassContext& context, const std::vector<uint32_t>& coarseNodes,
                       size_t begin, size_t end, std::vector<std::unique_ptr<ChunkMesher>>& meshers,
                       std::vector<BuiltChunk>& out, std::vector<ChunkSurface>* surfaces,
                       Progress& progress) {
  std::mutex failMutex;
  std::optional<Error> failure;
  parallelFor(end - begin, unsigned(meshers.size()), [&](size_t i, unsigned w) {
    {
      std::lock_guard lock(failMutex);
      if (failure) return;
    }
    const size_t k = begin + i;
    NodeRecord& node = context.nodes[coarseNodes[k]];
    const ChunkMesh mesh = meshers[w]->build(node.level, int32_t(node.x), int32_t(node.y));
    if (surfaces) (*surfaces)[k] = surfaceOf(mesh);
    auto blob = encodeChunk(mesh, context.budget, node, context.compressionLevel, context.payload);
    if (!blob) {
      std::lock_guard lock(failMutex);
      if (!failure) failure = blob.error();
      return;
    }
    out[k] = {coarseNodes[k], std::move(blob).value(), {}};
    progress.advance();
  });
  if (failure) return *failure;
  return {};
}

}  // namespace

Result<std::vector<BuiltChunk>> buildCoarseChunks(
    const ChunkPassContext& context, const std::vector<uint32_t>& coarseNodes,
    std::vector<std::unique_ptr<ChunkMesher>>& meshers, Progress& progress) {
  std::vector<BuiltChunk> out(coarseNodes.size());
  if (Status s = buildChunkRange(context, coarseNodes, 0, coarseNodes.size(), meshers, out, nullptr,
                                 progress);
      !s)
    return s.error();
  return out;
}

Result<std::vector<BuiltChunk>> buildCoarseChunksTopDown(
    const ChunkPassContext& context, const std::vector<uint32_t>& coarseNodes,
    std::vector<std::unique_ptr<ChunkMesher>>& meshers, SurfaceStore& surfaces,
    Progress& progress) {
  const std::vector<NodeRecord>& nodes = context.nodes;
  std::vector<BuiltChunk> out(coarseNodes.size());
  std::vector<ChunkSurface> built(coarseNodes.size());
  for (auto& m : meshers) {
    m->setMethod(context.mesher, context.firstGreedyLevel);
    m->shareSurfaces(&surfaces);
  }
  // coarseNodes is breadth-first: each level's run, parents before children.
  for (size_t begin = 0; begin < coarseNodes.size();) {
    const uint8_t level = nodes[coarseNodes[begin]].level;
    size_t end = begin;
    while (end < coarseNodes.size() && nodes[coarseNodes[end]].level == level) ++end;
    if (Status s =
            buildChunkRange(context, coarseNodes, begin, end, meshers, out, &built, progress);
        !s)
      return s.error();
    for (size_t k = begin; k < end; ++k) surfaces.add(std::move(built[k]));
    begin = end;
  }
  return out;
}

Status attachTextures(std::vector<BuiltChunk>& chunks, NodeTextures textures,
                      const std::vector<NodeRecord>& nodes) {
  std::unordered_map<uint32_t, size_t> index;
  for (size_t k = 0; k < chunks.size(); ++k) index.emplace(chunks[k].node, k);
  std::vector<uint8_t> attached(chunks.size(), 0);  // (empty for a node that inherits its texture)
  for (auto& [node, blob] : textures)
    if (auto k = index.find(node); k != index.end()) {
      chunks[k->second].texture = std::move(blob);
      attached[k->second] = 1;
    }
  for (size_t k = 0; k < chunks.size(); ++k)
    if (const BuiltChunk& c = chunks[k]; !attached[k])
      return Error{"internal error: chunk " + std::to_string(nodes[c.node].level) + "/" +
                   std::to_string(nodes[c.node].x) + "/" + std::to_string(nodes[c.node].y) +
                   " has no texture"};
  return {};
}

Status buildChunks(const TreeLayout& layout, const ErrorBudget& budget, const ActivationGrid& grid,
                   std::vector<NodeRecord>& nodes, HeightWindows& windows,
                   const HeightSampler* allHeights, SparseHeights* sparse,
                   const ChunkPassOptions& options, TilesetWriter& writer, Progress& progress) {
  const int32_t block = std::clamp(options.blockCells, layout.leafCells, layout.rootCells);
  const int32_t blockLevel = blockLevelOf(layout, block);
  const unsigned threads = std::max(1u, options.threads);
  const std::vector<uint32_t> blockNodes = blockNodesOf(nodes, blockLevel);
  const std::vector<uint32_t> coarseNodes = coarseNodesOf(nodes, blockLevel);

  const HeightSampler& coarseHeights = allHeights ? *allHeights : *sparse;
  std::vector<std::unique_ptr<ChunkMesher>> meshers(threads);
  for (auto& m : meshers) m = std::make_unique<ChunkMesher>(layout, budget, grid, coarseHeights);
  std::vector<BlockWindow> windowsOf(threads);

  std::unique_ptr<TexturePass> texturePass;
  if (options.textures) {
    texturePass = std::make_unique<TexturePass>(layout, *options.textures, nodes, threads);
    if (Status s = texturePass->open(); !s) return s;
  }
  ChunkPassContext context{
      layout,
      budget,
      nodes,
      block,
      options.compressionLevel,
      texturePass.get(),
      options.mesher,
      options.payload,
      firstGreedyLevel(blockLevel, allHeights ? CoarseHeights::kEvery : CoarseHeights::kSparse)};
  // The textures above the blocks are built as the blocks come in.
  std::optional<TilePyramid> pyramid;
  if (texturePass)
    pyramid.emplace(*texturePass, nodes, TilePyramid::buildableFrom(nodes, blockLevel, blockNodes));
  NodeTextures blockTextures(options.textures ? blockNodes.size() : 0);

  // Blobs go to the file in task order whatever order tasks finish in.
  std::mutex writeMutex;
  std::vector<std::vector<BuiltChunk>> done(blockNodes.size());
  std::vector<uint8_t> ready(blockNodes.size(), 0);
  size_t nextTask = 0;
  std::optional<Error> failure;
  std::atomic<bool> failed{false};
  auto fail = [&](Error e) {
    std::lock_guard lock(writeMutex);
    if (!failure) failure = std::move(e);
    failed = true;
  };
  auto append = [&](const BuiltChunk& chunk) -> Status {
    return appendChunk(writer, nodes[chunk.node], chunk.blob, chunk.texture);
  };

  progress.begin("meshing", nodes.size());
  // A greedy build that has every height meshes the levels at and above the blocks first, top
  // down, so that each block's chunks start from its greedy block-level chunk.
  std::optional<std::vector<BuiltChunk>> coarse;
  SurfaceStore surfaces;
  if (context.mesher == MeshMethod::kGreedy && context.firstGreedyLevel == 0) {
    auto built = buildCoarseChunksTopDown(context, coarseNodes, meshers, surfaces, progress);
    if (!built) return built.error();
    coarse = std::move(built).value();
  }
  parallelFor(blockNodes.size(), threads, [&](size_t task, unsigned w) {
    if (failed) return;
    const NodeRecord& b = nodes[blockNodes[task]];
    const BlockWindow* window = nullptr;
    if (allHeights) {
      meshers[w]->setHeights(*allHeights);
    } else {
      if (Status s = readBlockWindow(context, windows, int32_t(b.x) * block, int32_t(b.y) * block,
                                     block, windowsOf[w], w);
          !s)
        return fail(s.error());
      window = &windowsOf[w];
    }
    auto built = buildBlockChunks(context, blockNodes[task], window, *meshers[w], grid, windows, w);
    if (!built) return fail(built.error());
    if (options.madeTextures)
      for (BuiltChunk& chunk : built->chunks)
        chunk.texture = std::move((*options.madeTextures)[chunk.node]);
    for (size_t k = 0; k < built->chunks.size(); ++k) progress.advance();
    if (pyramid) {
      pyramid->add(blockNodes[task], std::move(built->tiles));
      blockTextures[task] = {blockNodes[task], std::move(built->blockTexture)};
    }
    if (sparse) sparse->recordPoints(built->points);
    std::lock_guard lock(writeMutex);
    done[task] = std::move(built->chunks);
    ready[task] = 1;
    for (; nextTask < done.size() && ready[nextTask]; ++nextTask) {
      for (const BuiltChunk& chunk : done[nextTask])
        if (Status s = append(chunk); !s) {
          if (!failure) failure = s.error();
          failed = true;
          return;
        }
      done[nextTask].clear();
      done[nextTask].shrink_to_fit();
    }
  });
  if (failure) return *failure;

  for (auto& m : meshers) m->setHeights(coarseHeights);
  if (pyramid)
    for (auto& t : pyramid->takeTextures()) blockTextures.push_back(std::move(t));
  if (options.madeTextures)
    for (uint32_t node : coarseNodes)
      blockTextures.emplace_back(node, std::move((*options.madeTextures)[node]));
  if (!coarse) {
    auto built = buildCoarseChunks(context, coarseNodes, meshers, progress);
    if (!built) return built.error();
    coarse = std::move(built).value();
  }
  if (pyramid || options.madeTextures)
    if (Status s = attachTextures(*coarse, std::move(blockTextures), nodes); !s) return s;
  for (const BuiltChunk& chunk : *coarse)
    if (Status s = append(chunk); !s) return s;
  progress.end();
  if (sparse && sparse->misses() > 0)
    return Error{"internal error: " + std::to_string(sparse->misses()) +
                 " heights were needed that the streamed build had not kept"};
  return {};
}

Status appendChunk(TilesetWriter& writer, NodeRecord& node, std::span<const uint8_t> blob,
                   std::span<const uint8_t> texture) {
  auto offset = writer.appendBlob(blob);
  if (!offset) return offset.error();
  node.blobOffset = *offset;
  if (!texture.empty()) {
    auto at = writer.appendBlob(texture);
    if (!at) return at.error();
    node.flags |= kNodeHasTexture;
    node.textureBytes = uint32_t(texture.size());
  }
  return {};
}

}  // namespace terralod
