#pragma once
// The full-resolution texels of the leaf chunks of one block: normals from the heightfield by
// central differences, the generated colour (hypsometric tint, bare rock on steep slopes, snow
// on high flat ground, darkened hollows as a baked ambient occlusion), and, with an image
// drape, the image's colour (the generated colour where the image has no data).
//
// Everything is computed from a window of heights around the block with a margin, so texels
// on a block's border come out exactly as the neighbouring block computes them.

#include <cstdint>
#include <vector>

#include "terralod/build/texel_tile.h"
#include "terralod/core/result.h"

namespace terralod {

class ImageDrape;
class HeightWindows;

struct SurfaceTexelOptions {
  double spacingX = 1, spacingY = 1;
  double zMin = 0, zMax = 1;  ///< the data's height range (for the colour ramp)
};

class BlockTexels {
 public:
  /// Samples of margin the window needs around a block.
  static constexpr int32_t kMargin = 9;

  explicit BlockTexels(const SurfaceTexelOptions& options) : mOptions(options) {}

  /// Reads the heights (and image texels, with `image`) for grid square [x0, x0 + cells]^2.
  Status load(HeightWindows& heights, unsigned worker, const ImageDrape* image, int32_t x0,
              int32_t y0, int32_t cells);

  /// Tiles of grid square [x0, x0 + cells]^2 (inside the loaded block) at full resolution:
  /// cells + 1 texels per side for normals, cells * refine + 1 for colour.
  TexelTile normals(int32_t x0, int32_t y0, int32_t cells) const;
  TexelTile colors(int32_t x0, int32_t y0, int32_t cells) const;

 private:
  float height(int32_t gx, int32_t gy) const {
    return mHeights[size_t(gy - mY0) * mSide + size_t(gx - mX0)];
  }
  void generatedColor(int32_t gx, int32_t gy, float* rgb) const;

  SurfaceTexelOptions mOptions;
  int32_t mX0 = 0, mY0 = 0, mSide = 0;  // window origin (grid) and side, margin included
  std::vector<float> mHeights;
  std::vector<double> mSums;  // summed-area table of the heights, (side + 1)^2
  uint32_t mRefine = 0;       // 0: no image
  int64_t mImageX0 = 0, mImageY0 = 0;
  int32_t mImageSide = 0;
  std::vector<uint8_t> mImage;  // RGBA8 over the block, fine grid
};

}  // namespace terralod
