#include "terralod/build/chunk_pass.h"

#include <algorithm>
#include <atomic>
#include <bit>
#include <cmath>
#include <deque>
#include <limits>
#include <mutex>
#include <optional>
#include <unordered_map>

#include "terralod/build/chunk_encoder.h"
#include "terralod/build/chunk_mesher.h"
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

// Heights of one block's window; anything outside it is a bug in the caller.
class WindowSampler final : public HeightSampler {
 public:
  void set(const float* values, int32_t x0, int32_t y0, int32_t side) {
    mValues = values;
    mX0 = x0;
    mY0 = y0;
    mSide = side;
  }
  double at(int32_t x, int32_t y) const override {
    const int32_t lx = x - mX0, ly = y - mY0;
    if (lx < 0 || ly < 0 || lx > mSide || ly > mSide) return std::nan("");
    return mValues[size_t(ly) * (mSide + 1) + lx];
  }

 private:
  const float* mValues = nullptr;
  int32_t mX0 = 0, mY0 = 0, mSide = 0;
};

// Meshes, quantises and encodes one chunk; fills in its node's statistics.
Result<std::vector<uint8_t>> buildChunk(ChunkMesher& mesher, const ErrorBudget& budget,
                                        NodeRecord& node, int compressionLevel) {
  const ChunkMesh mesh = mesher.build(node.level, int32_t(node.x), int32_t(node.y));
  for (const MeshVertex& v : mesh.vertices)
    if (!std::isfinite(v.z) || !std::isfinite(v.morphTarget))
      return Error{"internal error: chunk " + std::to_string(node.level) + "/" +
                   std::to_string(node.x) + "/" + std::to_string(node.y) +
                   " has a vertex without a height"};
  auto geometry = quantizeChunk(mesh, budget);
  if (!geometry) return geometry.error();
  std::vector<uint8_t> blob = encodeChunk(*geometry, compressionLevel);
  // Quantisation moves a drawn height (own or morphed) by up to half a step either way.
  const double halfStep = 0.5 * geometry->zStep;
  node.minZ = floatBelow(mesh.minZ - halfStep);
  node.maxZ = floatAbove(mesh.maxZ + halfStep);
  node.vertexCount = mesh.surfaceVertexCount;
  node.triangleCount = uint32_t(mesh.surfaceIndices.size() / 3);
  node.skirtTriangleCount = uint32_t(mesh.skirtIndices.size() / 3);
  node.maxSkirtDepth =
      floatAbove(*std::max_element(mesh.skirtDepth.begin(), mesh.skirtDepth.end()));
  node.blobBytes = uint32_t(blob.size());
  node.blobCrc = crc32Of(blob);
  return blob;
}

// A built chunk waiting for its turn to be written.
struct Built {
  uint32_t node = 0;
  std::vector<uint8_t> blob, texture;
};

}  // namespace

std::vector<NodeRecord> enumerateNodes(const TreeLayout& layout) {
  std::vector<NodeRecord> nodes;
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

Status buildChunks(const TreeLayout& layout, const ErrorBudget& budget, const ActivationGrid& grid,
                   std::vector<NodeRecord>& nodes, HeightWindows& windows,
                   const HeightSampler* allHeights, SparseHeights* sparse,
                   const ChunkPassOptions& options, TilesetWriter& writer, Progress& progress) {
  const int32_t block = std::clamp(options.blockCells, layout.leafCells, layout.rootCells);
  const int32_t blockLevel = std::countr_zero(uint32_t(layout.rootCells / block));
  const unsigned threads = std::max(1u, options.threads);
  std::vector<uint32_t> blockNodes, coarseNodes;
  for (uint32_t i = 0; i < nodes.size(); ++i) {
    if (nodes[i].level == blockLevel) blockNodes.push_back(i);
    if (nodes[i].level <= blockLevel) coarseNodes.push_back(i);
  }
  const uint8_t sparseActivation = budget.activationForLevel(blockLevel);

  struct Worker {
    std::unique_ptr<ChunkMesher> mesher;
    std::vector<float> window;
    WindowSampler sampler;
  };
  std::vector<Worker> workers(threads);
  const HeightSampler& coarseHeights = allHeights ? *allHeights : *sparse;
  for (Worker& w : workers)
    w.mesher = std::make_unique<ChunkMesher>(layout, budget, grid, coarseHeights);

  std::unique_ptr<TexturePass> texturePass;
  if (options.textures) {
    texturePass = std::make_unique<TexturePass>(layout, *options.textures, nodes, threads);
    if (Status s = texturePass->open(); !s) return s;
  }
  // Block nodes' texture tiles, kept for the coarser levels' textures.
  std::vector<ChunkTiles> blockTiles(options.textures ? blockNodes.size() : 0);
  std::vector<std::vector<uint8_t>> blockTextures(blockTiles.size());

  // Blobs go to the file in task order whatever order tasks finish in.
  std::mutex writeMutex;
  std::vector<std::vector<Built>> done(blockNodes.size());
  std::vector<uint8_t> ready(blockNodes.size(), 0);
  size_t nextTask = 0;
  std::optional<Error> failure;
  std::atomic<bool> failed{false};
  auto fail = [&](Error e) {
    std::lock_guard lock(writeMutex);
    if (!failure) failure = std::move(e);
    failed = true;
  };
  auto append = [&](uint32_t node, const std::vector<uint8_t>& blob,
                    const std::vector<uint8_t>& texture) -> Status {
    auto offset = writer.appendBlob(blob);
    if (!offset) return offset.error();
    nodes[node].blobOffset = *offset;
    if (!texture.empty()) {
      auto at = writer.appendBlob(texture);
      if (!at) return at.error();
      nodes[node].flags |= kNodeHasTexture;
      nodes[node].textureBytes = uint32_t(texture.size());
    }
    return {};
  };

  progress.begin("meshing", nodes.size());
  parallelFor(blockNodes.size(), threads, [&](size_t task, unsigned w) {
    if (failed) return;
    Worker& worker = workers[w];
    const NodeRecord& b = nodes[blockNodes[task]];
    const int32_t x0 = int32_t(b.x) * block, y0 = int32_t(b.y) * block;
    if (allHeights) {
      worker.mesher->setHeights(*allHeights);
    } else {
      worker.window.resize(size_t(block + 1) * (block + 1));
      if (Status s = windows.read(x0, y0, block + 1, block + 1, worker.window.data(), w); !s)
        return fail(s.error());
      worker.sampler.set(worker.window.data(), x0, y0, block);
      worker.mesher->setHeights(worker.sampler);
    }
    std::vector<Built> built;
    std::deque<uint32_t> queue;
    auto pushChildren = [&](uint32_t i) {
      const NodeRecord& n = nodes[i];
      for (uint32_t c = 0; c < uint32_t(std::popcount(unsigned(n.childMask))); ++c)
        queue.push_back(n.firstChild + c);
    };
    pushChildren(blockNodes[task]);
    while (!queue.empty()) {
      const uint32_t i = queue.front();
      queue.pop_front();
      auto blob = buildChunk(*worker.mesher, budget, nodes[i], options.compressionLevel);
      if (!blob) return fail(blob.error());
      built.push_back({i, std::move(blob).value(), {}});
      pushChildren(i);
      progress.advance();
    }
    if (texturePass) {
      std::vector<std::pair<uint32_t, std::vector<uint8_t>>> textures;
      auto tiles = texturePass->buildBlock(blockNodes[task], windows, w, textures);
      if (!tiles) return fail(tiles.error());
      blockTiles[task] = std::move(tiles).value();
      std::unordered_map<uint32_t, size_t> where;
      for (size_t k = 0; k < built.size(); ++k) where.emplace(built[k].node, k);
      for (auto& [node, blob] : textures) {
        if (node == blockNodes[task])
          blockTextures[task] = std::move(blob);
        else
          built[where.at(node)].texture = std::move(blob);
      }
    }
    if (sparse) {
      // Vertices the block-level and coarser chunks will need, for after the window is gone.
      std::vector<std::pair<uint64_t, float>> points;
      const int32_t x1 = std::min(x0 + block, layout.cellsX),
                    y1 = std::min(y0 + block, layout.cellsY);
      for (int32_t y = y0; y <= y1; ++y)
        for (int32_t x = x0; x <= x1; ++x)
          if (grid.get(x, y) >= sparseActivation)
            points.emplace_back(SparseHeights::key(x, y),
                                worker.window[size_t(y - y0) * (block + 1) + (x - x0)]);
      sparse->recordPoints(points);
    }
    std::lock_guard lock(writeMutex);
    done[task] = std::move(built);
    ready[task] = 1;
    for (; nextTask < done.size() && ready[nextTask]; ++nextTask) {
      for (const Built& chunk : done[nextTask])
        if (Status s = append(chunk.node, chunk.blob, chunk.texture); !s) {
          if (!failure) failure = s.error();
          failed = true;
          return;
        }
      done[nextTask].clear();
      done[nextTask].shrink_to_fit();
    }
  });
  if (failure) return *failure;

  std::vector<std::vector<uint8_t>> coarseBlobs(coarseNodes.size());
  for (Worker& w : workers) w.mesher->setHeights(coarseHeights);
  parallelFor(coarseNodes.size(), threads, [&](size_t k, unsigned w) {
    if (failed) return;
    auto blob =
        buildChunk(*workers[w].mesher, budget, nodes[coarseNodes[k]], options.compressionLevel);
    if (!blob) return fail(blob.error());
    coarseBlobs[k] = std::move(blob).value();
    progress.advance();
  });
  if (failure) return *failure;
  std::vector<std::vector<uint8_t>> coarseTextures(coarseNodes.size());
  if (texturePass) {
    // Level by level up from the block level, each from its children's tiles.
    std::unordered_map<uint32_t, ChunkTiles> tiles;
    for (size_t t = 0; t < blockNodes.size(); ++t)
      tiles.emplace(blockNodes[t], std::move(blockTiles[t]));
    std::unordered_map<uint32_t, size_t> coarseIndex;
    for (size_t k = 0; k < coarseNodes.size(); ++k) coarseIndex.emplace(coarseNodes[k], k);
    for (size_t t = 0; t < blockNodes.size(); ++t)
      coarseTextures[coarseIndex.at(blockNodes[t])] = std::move(blockTextures[t]);
    for (int32_t level = blockLevel - 1; level >= 0; --level) {
      std::vector<uint32_t> atLevel;
      for (uint32_t i : coarseNodes)
        if (nodes[i].level == level) atLevel.push_back(i);
      std::vector<ChunkTiles> made(atLevel.size());
      parallelFor(atLevel.size(), threads, [&](size_t k, unsigned) {
        const NodeRecord& n = nodes[atLevel[k]];
        std::array<const ChunkTiles*, 4> children{};
        uint32_t c = n.firstChild;
        for (int q = 0; q < 4; ++q)
          if (n.childMask & (1u << q)) children[size_t(q)] = &tiles.at(c++);
        made[k] = texturePass->fromChildren(atLevel[k], children);
        coarseTextures[coarseIndex.at(atLevel[k])] = texturePass->encode(atLevel[k], made[k]);
      });
      for (uint32_t i : atLevel)
        for (uint32_t j = 0; j < uint32_t(std::popcount(unsigned(nodes[i].childMask))); ++j)
          tiles.erase(nodes[i].firstChild + j);
      for (size_t k = 0; k < atLevel.size(); ++k) tiles.emplace(atLevel[k], std::move(made[k]));
    }
  }
  for (size_t k = 0; k < coarseNodes.size(); ++k)
    if (Status s = append(coarseNodes[k], coarseBlobs[k], coarseTextures[k]); !s) return s;
  progress.end();
  if (sparse && sparse->misses() > 0)
    return Error{"internal error: " + std::to_string(sparse->misses()) +
                 " heights were needed that the streamed build had not kept"};
  return {};
}

}  // namespace terralod
