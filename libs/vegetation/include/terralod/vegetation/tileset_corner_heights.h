#pragma once
// The heights vegetation tiles stand on, from a tileset: the finest chunk over each tile corner
// (static or VIPM, at its full detail: the surface within the finest level's error of the
// data) read when first wanted, its triangles sampled at the tiling's corner lattice, and kept
// per chunk while they fit a byte budget. Render thread only.

#include <cstdint>
#include <functional>
#include <list>
#include <string>
#include <unordered_map>
#include <vector>

#include "terralod/format/tileset_reader.h"
#include "terralod/runtime/chunk_tree.h"
#include "terralod/vegetation/vegetation_field.h"

namespace terralod::veg {

class TilesetCornerHeights final : public CornerHeights {
 public:
  /// `log` gets one line per chunk that cannot be read (its tiles are left out).
  TilesetCornerHeights(const TilesetReader& tileset, const ChunkTree& tree, double tileSize,
                       uint64_t budgetBytes, std::function<void(const std::string&)> log = {});

  std::optional<std::array<float, 4>> tileCorners(uint32_t x, uint32_t y) override;

  uint64_t residentBytes() const { return mResidentBytes; }
  uint64_t chunksRead() const { return mChunksRead; }

 private:
  struct Page {  // the corner lattice points over one finest chunk
    int64_t i0 = 0, j0 = 0;
    int columns = 0, rows = 0;
    std::vector<float> heights;  // NaN: no triangle over the point
    std::list<uint32_t>::iterator lru;
  };
  std::optional<float> corner(int64_t i, int64_t j);
  uint32_t leafAt(double x, double y) const;
  const Page* page(uint32_t leaf);

  const TilesetReader& mTileset;
  const ChunkTree& mTree;
  double mTileSize;
  uint64_t mBudget;
  std::function<void(const std::string&)> mLog;
  std::unordered_map<uint32_t, Page> mPages;
  std::list<uint32_t> mLru;  // most recent first
  std::unordered_map<uint32_t, bool> mFailed;
  uint64_t mResidentBytes = 0, mChunksRead = 0;
};

}  // namespace terralod::veg
