#pragma once
// The texture quadtree made during pass 1, from the windows pass 1 reads anyway (with the
// texture pass's margin), so that a textured build need not keep the raster for pass 2: each
// block's subtree of tiles as its window comes in (TexturePass::buildBlock), the levels above
// the blocks in a TilePyramid as blocks finish, and every node's encoded texture blob held
// until pass 2 writes it beside the node's mesh. The textures are a function of the heights
// alone (not of the error budget), so a second pass-1 attempt does not redo them.

#include <cstdint>
#include <memory>
#include <vector>

#include "terralod/build/activation_pass.h"
#include "terralod/build/texture_pass.h"
#include "terralod/build/tile_pyramid.h"
#include "terralod/build/tree_layout.h"
#include "terralod/core/result.h"
#include "terralod/format/tileset_format.h"

namespace terralod {

class PassOneTextures final : public BlockWindowUser {
 public:
  /// `nodes` is enumerateNodes(layout) and outlives this; `blockCells` the pass's block side.
  PassOneTextures(const TreeLayout& layout, const TextureBuild& build,
                  const std::vector<NodeRecord>& nodes, int32_t blockCells, unsigned threads);
  ~PassOneTextures() override;
  /// Opens the per-thread image readers.
  Status open();

  /// The bytes of every node's texture blocks (all mips, before zstd): about what is held from
  /// pass 1 to pass 2, for deciding whether that fits the memory budget.
  static uint64_t blockBytes(const TextureBuild& build, const std::vector<NodeRecord>& nodes);

  int32_t margin() const override;
  Status useBlock(int32_t x0, int32_t y0, int32_t side, const float* heights,
                  unsigned worker) override;

  /// After pass 1: every node's texture blob, by node index (empty for a node of an inherited
  /// level); an internal error when a block never came in.
  Result<std::vector<std::vector<uint8_t>>> take();

 private:
  const TreeLayout& mLayout;
  int32_t mBlock = 0;
  TexturePass mPass;
  TilePyramid mPyramid;
  std::vector<uint32_t> mBlockNodes;         // by block, row-major over the grid
  std::vector<std::vector<uint8_t>> mBlobs;  // by node
  std::vector<uint8_t> mDone;                // by block
};

}  // namespace terralod
