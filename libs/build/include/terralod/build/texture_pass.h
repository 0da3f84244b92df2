#pragma once
// The texture quadtree, built alongside the chunk meshes: leaf chunks get their colour and
// normal tiles from the full-resolution heights (and draped image) of their block, every other
// chunk from its four children's tiles (so the whole pyramid is built from the full-resolution
// data with one pass over it). Tile sizes follow the TexturePlan.

#include <array>
#include <cstdint>
#include <memory>
#include <utility>
#include <vector>

#include "terralod/build/height_source.h"
#include "terralod/build/surface_texels.h"
#include "terralod/build/texel_tile.h"
#include "terralod/build/texture_plan.h"
#include "terralod/build/tree_layout.h"
#include "terralod/core/result.h"
#include "terralod/format/texture_codec.h"
#include "terralod/format/tileset_format.h"

namespace terralod {

class ImageDrape;

struct TextureBuild {
  std::vector<TextureLevel> plan;  ///< per level, root first
  SurfaceTexelOptions surface;
  const ImageDrape* image = nullptr;  ///< null: the generated colour
  /// What the colour tiles hold: the colour (BC1: a draped image or the generated colour
  /// baked) or the shade the shader makes the generated colour from (BC4).
  TextureLayerKind colourKind = TextureLayerKind::kShade;
  TextureEncoding colourEncoding() const {
    return colourKind == TextureLayerKind::kShade ? TextureEncoding::kBc4 : TextureEncoding::kBc1;
  }
  int zstdLevel = 3;  ///< for the texture blobs (`--zstd-level`)
};

/// One layer of a chunk while the pyramid is built: every mip level, as floats (for the parent
/// to build on) and encoded (what is stored, and what a parent can reuse).
struct LayerLevels {
  std::vector<TexelTile> levels;
  std::vector<std::vector<uint8_t>> blocks;
};

struct ChunkTiles {
  LayerLevels color, normal;  ///< color: the colour or shade tiles (TextureBuild::colourKind)
};

class MosaicBuilder;

/// A node's level-0 tiles while its children come in one by one (TilePyramid).
struct PartialTiles {
  PartialTiles();
  PartialTiles(PartialTiles&&) noexcept;
  PartialTiles& operator=(PartialTiles&&) noexcept;
  ~PartialTiles();
  std::unique_ptr<MosaicBuilder> color, normal;
};

class TexturePass {
 public:
  TexturePass(const TreeLayout& layout, const TextureBuild& build,
              const std::vector<NodeRecord>& nodes, unsigned threads);
  ~TexturePass();
  /// Opens the per-thread image readers.
  Status open();

  /// Tiles of `root` and every node below it, bottom-up, for the block whose square is
  /// `root`'s. Each node's texture blob is appended to `blobs`; `root`'s tiles are returned
  /// for its ancestors.
  Result<ChunkTiles> buildBlock(uint32_t root, HeightWindows& heights, unsigned worker,
                                std::vector<std::pair<uint32_t, std::vector<uint8_t>>>& blobs);

  /// Tiles of a node from its children's (entries null where a child does not exist). A
  /// parent's mip levels are its children's levels side by side wherever the sizes allow (its
  /// mip m is their mip m when it holds them unresampled, their mip m + 1 when it halves
  /// them), reusing their encoded blocks: the same pixels on both sides of a split. The
  /// children's tiles are used up (emptied layer by layer as the parent's are made).
  ChunkTiles fromChildren(uint32_t node, const std::array<ChunkTiles*, 4>& children) const;
  /// The same made child by child: startParent (once, with the first child to come; not
  /// thread-safe), addChild for each child as it comes (children concurrently; the child's
  /// level-0 floats are used and freed), then finishParent with every child's remaining tiles.
  void startParent(uint32_t node, PartialTiles& partial, const ChunkTiles& child) const;
  void addChild(PartialTiles& partial, size_t quadrant, ChunkTiles& child) const;
  ChunkTiles finishParent(uint32_t node, PartialTiles& partial,
                          const std::array<ChunkTiles*, 4>& children) const;
  /// Frees what fromChildren will not read of a node's tiles when it builds the node's parent
  /// (float levels and encoded blocks its parent does not take side by side; their sizes stay),
  /// for tiles that wait for a sibling or are handed on.
  void keepWhatTheParentReads(uint32_t node, ChunkTiles& tiles) const;
  /// The stored texture blob of a node's tiles; empty for a node of an inherited level (it
  /// draws its parent's texture).
  std::vector<uint8_t> encode(uint32_t node, const ChunkTiles& tiles) const;

 private:
  const TreeLayout& mLayout;
  const TextureBuild& mBuild;
  const std::vector<NodeRecord>& mNodes;
  std::vector<std::unique_ptr<ImageDrape>> mImages;  // per worker
  std::vector<std::unique_ptr<BlockTexels>> mTexels;
};

}  // namespace terralod
