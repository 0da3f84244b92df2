#include "terralod/measure/texture_metrics.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <vector>

namespace terralod {

void addTexelDensity(const View& view, const ChunkTree& tree, const GpuChunkStore& store,
                     std::span<const SelectedChunk> chunks, TexelDensity& density) {
  const auto spacing = tree.spacing();
  const double cellMetres = std::max(spacing[0], spacing[1]);
  for (const SelectedChunk& s : chunks) {
    // (A chunk that inherits its texture draws its part of an ancestor's, 2^depth a side.)
    const DrawnTexture drawn = drawnTexture(tree, store, s.node);
    if (!drawn.chunk) continue;
    const ChunkNode& n = tree.node(s.node);
    const double distance = distanceToBox(view.camera.eye, n.box);
    const double side = tree.chunkCells(int(drawn.level)) * cellMetres;
    // A shade layer is not what the colour's detail comes from (the normal map and the drawn
    // height are): it is half the normal map's resolution by design (halveColourTiles).
    for (const TextureSlot* slot : {&drawn.chunk->color, &drawn.chunk->normal}) {
      if (slot == &drawn.chunk->color && drawn.chunk->shaded) continue;
      const double texel = side / double(slot->size - 1);
      const double pixels = distance > 0 ? texel * view.pixelsPerRadian / distance
                                         : std::numeric_limits<double>::infinity();
      if (slot->flags & kTextureSourceLimited) {
        density.sourceLimitedMax = std::max(density.sourceLimitedMax, pixels);
        density.anySourceLimited = true;
      } else {
        density.max = std::max(density.max, pixels);
        density.any = true;
      }
    }
  }
}

double meanAbsoluteDifference(const Image& a, const Image& b) {
  uint64_t sum = 0;
  const size_t n = std::min(a.rgba.size(), b.rgba.size());
  for (size_t i = 0; i < n; i += 4)
    for (size_t c = 0; c < 3; ++c)
      sum += uint64_t(std::abs(int(a.rgba[i + c]) - int(b.rgba[i + c])));
  return n ? double(sum) / double(n / 4 * 3) : 0.0;
}

bool selectionsDiffer(std::span<const SelectedChunk> a, std::span<const SelectedChunk> b) {
  if (a.size() != b.size()) return true;
  std::vector<uint32_t> x, y;
  for (const SelectedChunk& s : a) x.push_back(s.node);
  for (const SelectedChunk& s : b) y.push_back(s.node);
  std::sort(x.begin(), x.end());
  std::sort(y.begin(), y.end());
  return x != y;
}

}  // namespace terralod
