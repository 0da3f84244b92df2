#pragma once
// The texture pyramid above the blocks, built as the blocks come in: each child's level 0 goes
// into its parent's as it comes (TexturePass::addChild: the parent's texels it alone reaches
// at once, the seams kept), and whichever thread adds the last child finishes the parent
// (finishParent). So a node waiting for siblings holds one partial level 0 and its children's
// small mip levels, not up to three children's full tiles. The local build gives it every block; a
// pass-2 job of a staged build gives it its own blocks and hands on the tiles of the nodes it could
// not finish (its frontier), from which the coarse job builds the rest with a second pyramid. Every
// node's texture is a function of the tiles below it alone, so any split gives the same bytes.

#include <cstdint>
#include <functional>
#include <mutex>
#include <unordered_map>
#include <utility>
#include <vector>

#include "terralod/build/texture_pass.h"
#include "terralod/format/tileset_format.h"

namespace terralod {

class TilePyramid {
 public:
  /// Builds the nodes marked in `builds` (by node index); the caller adds tiles for every
  /// child of each of them (directly, or by letting the pyramid build it).
  /// Where built nodes' texture blobs go (from any thread) instead of takeTextures.
  using TextureSink = std::function<void(uint32_t node, std::vector<uint8_t> texture)>;

  TilePyramid(const TexturePass& pass, const std::vector<NodeRecord>& nodes,
              std::vector<uint8_t> builds, TextureSink sink = {});

  /// Adds a node's tiles, then builds every ancestor whose children are then all in.
  /// Thread-safe; the building happens on the calling thread, outside the lock.
  void add(uint32_t node, ChunkTiles tiles);

  /// The encoded textures of the nodes built so far (by node, ascending; none with a sink).
  std::vector<std::pair<uint32_t, std::vector<uint8_t>>> takeTextures();
  /// The tiles of the nodes whose parent this pyramid does not build (by node, ascending).
  std::vector<std::pair<uint32_t, ChunkTiles>> takeFrontier();

  /// Whether each node (by index) is above `blockLevel` and every block-level node below it
  /// is one of `blocks`: what a pyramid given just those blocks can build.
  static std::vector<uint8_t> buildableFrom(const std::vector<NodeRecord>& nodes,
                                            int32_t blockLevel,
                                            const std::vector<uint32_t>& blocks);
  /// The frontier a pyramid that `builds` those nodes leaves when given `blocks` (ascending).
  static std::vector<uint32_t> frontierOf(const std::vector<NodeRecord>& nodes,
                                          const std::vector<uint8_t>& builds,
                                          const std::vector<uint32_t>& blocks);
  /// Every ancestor of `frontier`'s nodes: what a pyramid given them builds.
  static std::vector<uint8_t> ancestorsOf(const std::vector<NodeRecord>& nodes,
                                          const std::vector<uint32_t>& frontier);

 private:
  const TexturePass& mPass;
  const std::vector<NodeRecord>& mNodes;
  const std::vector<uint8_t> mBuilds;
  const TextureSink mSink;
  std::mutex mMutex;
  std::vector<uint8_t> mMissing;                        // children not yet in, per node it builds
  std::unordered_map<uint32_t, ChunkTiles> mWaiting;    // tiles of nodes whose parent is not built
  std::unordered_map<uint32_t, PartialTiles> mPartial;  // level 0 of parents being built
  std::vector<std::pair<uint32_t, std::vector<uint8_t>>> mTextures;
  std::vector<std::pair<uint32_t, ChunkTiles>> mFrontier;
};

}  // namespace terralod
