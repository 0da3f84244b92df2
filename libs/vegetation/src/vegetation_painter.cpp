#include "terralod/vegetation/vegetation_painter.h"

#include <chrono>

namespace terralod::veg {

Result<std::unique_ptr<VegetationPainter>> VegetationPainter::open(const std::string& pathOrUrl,
                                                                   const TilesetReader& tileset,
                                                                   const ChunkTree& tree,
                                                                   VegetationOptions options) {
  auto file = VegetationReader::openPathOrUrl(pathOrUrl);
  if (!file) return file.error();
  return std::unique_ptr<VegetationPainter>(
      new VegetationPainter(std::move(file).value(), tileset, tree, std::move(options)));
}

VegetationPainter::VegetationPainter(std::unique_ptr<VegetationReader> file,
                                     const TilesetReader& tileset, const ChunkTree& tree,
                                     VegetationOptions options)
    : mFile(std::move(file)),
      mOptions(std::move(options)),
      mLayout(FieldLayout::over(mFile->header().settings, tree.extent().max[0],
                                tree.extent().max[1], mOptions.seed)),
      mLdis(*mFile, mOptions.ldiBudgetBytes, mOptions.log),
      mHeights(tileset, tree, mLayout.tileSize, mOptions.heightBudgetBytes, mOptions.log) {}

void VegetationPainter::paint(const View& view, const PictureSpans& picture) {
  mLast = {};
  const auto start = std::chrono::steady_clock::now();
  const std::vector<TileDraw> tiles =
      selectTiles(mLayout, view, mHeights, mOptions.field, &mLast.field);
  mLast.selectMs =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  const double readBefore = mLdis.stats().readMs;
  mLast.warp = mWarper.warp(tiles, mLdis, view, mOptions.warp, picture);
  mLast.readMs = mLdis.stats().readMs - readBefore;
  mLast.residentBytes = mLdis.stats().residentBytes + mHeights.residentBytes();
}

}  // namespace terralod::veg
