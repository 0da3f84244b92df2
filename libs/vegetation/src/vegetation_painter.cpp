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

namespace {

uint64_t keyOf(const TileDraw& t) {
  return uint64_t(t.y) << 32 | t.x;
}

bool sameLdis(const std::pair<std::array<TileLdi, 4>, int>& a, const TileDraw& t) {
  if (a.second != t.ldiCount) return false;
  for (int k = 0; k < t.ldiCount; ++k)
    if (a.first[size_t(k)].resolution != t.ldis[size_t(k)].resolution ||
        a.first[size_t(k)].direction != t.ldis[size_t(k)].direction)
      return false;
  return true;
}

// A tile drawn with the LDIs it chose last frame, at this frame's opacities: those it still
// draws as now; one it no longer draws at its full range fade if it drew it alone, else not
// at all (the far end of a blend, faded out).
void usePrevious(TileDraw& t, const std::pair<std::array<TileLdi, 4>, int>& previous) {
  std::array<TileLdi, 4> ldis{};
  for (int k = 0; k < previous.second; ++k) {
    TileLdi l = previous.first[size_t(k)];
    l.opacity = previous.second == 1 ? t.opacity : 0.0f;
    for (int j = 0; j < t.ldiCount; ++j)
      if (t.ldis[size_t(j)].resolution == l.resolution &&
          t.ldis[size_t(j)].direction == l.direction)
        l.opacity = t.ldis[size_t(j)].opacity;
    ldis[size_t(k)] = l;
  }
  t.ldis = ldis;
  t.ldiCount = previous.second;
}

}  // namespace

void VegetationPainter::paint(const View& view, const PictureSpans& picture) {
  mLast = {};
  const auto start = std::chrono::steady_clock::now();
  std::vector<TileDraw> tiles = selectTiles(mLayout, view, mHeights, mOptions.field, &mLast.field);
  if (mMode == PaintMode::kFrame) {
    mPrevious = std::move(mCurrent);
    mCurrent.clear();
    mChoicesChanged = false;
    for (const TileDraw& t : tiles) {
      mCurrent.emplace(keyOf(t), std::pair{t.ldis, t.ldiCount});
      const auto it = mPrevious.find(keyOf(t));
      if (it != mPrevious.end() && !sameLdis(it->second, t)) mChoicesChanged = true;
    }
  } else if (mMode == PaintMode::kPreviousChoices) {
    for (TileDraw& t : tiles)
      if (const auto it = mPrevious.find(keyOf(t)); it != mPrevious.end())
        usePrevious(t, it->second);
  }
  mLast.selectMs =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  const double readBefore = mLdis.stats().readMs;
  mLast.warp = mWarper.warp(tiles, mLdis, view, mOptions.warp, picture);
  mLast.readMs = mLdis.stats().readMs - readBefore;
  mLast.residentBytes = mLdis.stats().residentBytes + mHeights.residentBytes();
}

}  // namespace terralod::veg
