#include "terralod/measure/export_texture.h"

#include <stb_image_write.h>

#include <algorithm>
#include <cmath>

#include "terralod/format/chunk_position.h"
#include "terralod/format/node_colour.h"

// Debian's libstb ships the stb implementations compiled (libstb.so), so no
// STB_*_IMPLEMENTATION here.

namespace terralod {
namespace {

constexpr uint32_t kMaxSamplesPerAxis = 8;

// Each level's colour tile size (texels a side): from the metadata's "texture" "levels" when
// it has them all, else from the first chunk of each level.
Result<std::vector<uint32_t>> levelColorSizes(const TilesetReader& tileset) {
  const uint32_t levels = tileset.header().levelCount;
  std::vector<uint32_t> sizes;
  for (const TextureLevelSizes& l : tileset.metadata().textureLevels) sizes.push_back(l.color);
  if (sizes.size() == levels) return sizes;
  sizes.assign(levels, 0);
  for (uint32_t i = 0; i < tileset.nodes().size(); ++i) {
    const uint32_t level = tileset.nodes()[i].level;
    if (sizes[level]) continue;
    auto size = nodeColourSize(tileset, i);
    if (!size) return size.error();
    if (*size == 0)
      return makeError(tileset.name(), "chunk " + std::to_string(i) + " has no colour");
    sizes[level] = *size;
  }
  return sizes;
}

double longCells(const TilesetHeader& h) {
  return double(std::max(h.sourceColumns, h.sourceRows) - 1);
}

// Texels of `level` across the longer side: a tile of `size` texels spans the chunk's cells
// with size - 1 texel intervals.
double levelResolution(const TilesetHeader& h, uint32_t level, uint32_t size) {
  return longCells(h) * double(size - 1) / double(h.chunkCells(int32_t(level)));
}

void appendBytes(void* context, void* data, int size) {
  auto* bytes = static_cast<std::vector<uint8_t>*>(context);
  const auto* begin = static_cast<const uint8_t*>(data);
  bytes->insert(bytes->end(), begin, begin + size);
}

}  // namespace

Result<double> fullTextureResolution(const TilesetReader& tileset) {
  auto sizes = levelColorSizes(tileset);
  if (!sizes) return sizes.error();
  const uint32_t finest = tileset.header().levelCount - 1;
  return levelResolution(tileset.header(), finest, sizes->back());
}

Result<ExportTexture> assembleTexture(const TilesetReader& tileset, uint32_t longSide,
                                      Progress& progress) {
  const TilesetHeader& h = tileset.header();
  auto sizes = levelColorSizes(tileset);
  if (!sizes) return sizes.error();
  ExportTexture out;
  out.level = h.levelCount - 1;
  for (uint32_t level = 0; level < h.levelCount; ++level)
    if (levelResolution(h, level, (*sizes)[level]) >= longSide) {
      out.level = level;
      break;
    }
  out.levelTexels = levelResolution(h, out.level, (*sizes)[out.level]);

  const double cellsX = std::max(1u, h.sourceColumns - 1), cellsY = std::max(1u, h.sourceRows - 1);
  const bool wide = cellsX >= cellsY;
  const uint32_t shortSide = uint32_t(std::max<long long>(
      1, std::llround(double(longSide) * (wide ? cellsY / cellsX : cellsX / cellsY))));
  out.width = wide ? longSide : shortSide;
  out.height = wide ? shortSide : longSide;
  const uint32_t k = std::clamp<uint32_t>(uint32_t(std::ceil(out.levelTexels / longSide - 1e-9)), 1,
                                          kMaxSamplesPerAxis);
  const size_t pixels = size_t(out.width) * out.height;
  std::vector<float> sums(pixels * 3, 0.0f);
  std::vector<uint8_t> counts(pixels, 0);
  // Pixel (i, j) is x ∈ [i, i + 1)·cellsX/width cells, and row j counts from the north.
  const double cellsPerPixelX = cellsX / out.width, cellsPerPixelY = cellsY / out.height;

  uint64_t chunks = 0;
  for (const NodeRecord& n : tileset.nodes()) chunks += n.level == out.level;
  NodeColours colours(tileset);
  progress.begin("reading texture", chunks);
  const double side = h.chunkCells(int32_t(out.level));
  for (uint32_t i = 0; i < tileset.nodes().size(); ++i) {
    const NodeRecord& node = tileset.nodes()[i];
    if (node.level != out.level) continue;
    auto colour = colours.read(i);
    if (!colour) return colour.error();
    if (colour->rgb.empty())
      return makeError(tileset.name() + " chunk " + std::to_string(i), "has no colour texture");
    const uint32_t size = colour->size;
    const std::vector<uint8_t>& tile = colour->rgb;
    const auto origin = chunkCellOrigin(h, node);
    const double x0 = double(origin[0]), y0 = double(origin[1]);
    const double texelsPerCell = double(size - 1) / side;
    // Pixels that may have samples inside the chunk's square [x0, x0 + side) x [y0, y0 + side).
    const auto clampPixel = [](double p, uint32_t n) {
      return uint32_t(std::clamp(p, 0.0, double(n)));
    };
    const uint32_t i0 = clampPixel(std::floor(x0 / cellsPerPixelX), out.width),
                   i1 = clampPixel(std::ceil((x0 + side) / cellsPerPixelX), out.width);
    const uint32_t j0 = clampPixel(std::floor((cellsY - y0 - side) / cellsPerPixelY), out.height),
                   j1 = clampPixel(std::ceil((cellsY - y0) / cellsPerPixelY), out.height);
    for (uint32_t j = j0; j < j1; ++j)
      for (uint32_t b = 0; b < k; ++b) {
        const double y = cellsY - (j + (b + 0.5) / k) * cellsPerPixelY;
        if (y < y0 || y >= y0 + side) continue;
        const double fy = (y - y0) * texelsPerCell;
        const uint32_t ty = std::min(uint32_t(fy), size - 2);
        const float wy = float(fy - ty);
        for (uint32_t ip = i0; ip < i1; ++ip)
          for (uint32_t a = 0; a < k; ++a) {
            const double x = (ip + (a + 0.5) / k) * cellsPerPixelX;
            if (x < x0 || x >= x0 + side) continue;
            const double fx = (x - x0) * texelsPerCell;
            const uint32_t tx = std::min(uint32_t(fx), size - 2);
            const float wx = float(fx - tx);
            const uint8_t* t00 = &tile[(size_t(ty) * size + tx) * 3];
            const uint8_t* t10 = t00 + 3;
            const uint8_t* t01 = t00 + size_t(size) * 3;
            const uint8_t* t11 = t01 + 3;
            const size_t pixel = size_t(j) * out.width + ip;
            for (size_t c = 0; c < 3; ++c)
              sums[pixel * 3 + c] += (1 - wy) * ((1 - wx) * t00[c] + wx * t10[c]) +
                                     wy * ((1 - wx) * t01[c] + wx * t11[c]);
            ++counts[pixel];
          }
      }
    progress.advance();
  }
  progress.end();

  out.rgb.resize(pixels * 3);
  for (size_t p = 0; p < pixels; ++p) {
    if (counts[p] == 0)
      return makeError(tileset.name(), "the chunks of level " + std::to_string(out.level) +
                                           " do not cover the data (pixel " +
                                           std::to_string(p % out.width) + "," +
                                           std::to_string(p / out.width) + " of the texture)");
    for (size_t c = 0; c < 3; ++c)
      out.rgb[p * 3 + c] =
          uint8_t(std::clamp(std::lround(sums[p * 3 + c] / float(counts[p])), 0L, 255L));
  }
  return out;
}

Result<std::vector<uint8_t>> encodePng(const ExportTexture& texture, const std::string& subject) {
  std::vector<uint8_t> png;
  if (!stbi_write_png_to_func(appendBytes, &png, int(texture.width), int(texture.height), 3,
                              texture.rgb.data(), int(texture.width * 3)))
    return makeError(subject, "PNG encoding of the texture failed");
  return png;
}

}  // namespace terralod
