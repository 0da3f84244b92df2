#pragma once
// The full-resolution texels of the leaf chunks of one block: normals from the heightfield by
// central differences, the shade the shader's generated colour needs (format/generated_colour.h),
// or the colour itself: the generated colour baked, or with an image drape, the image's colour
// (the generated colour where the image has no data).
//
// The generated colour (format/generated_colour.h) darkens hollows (below the mean of the
// 17 x 17 samples around them) as a baked ambient occlusion, and is water (kWaterColor) where
// the ground is water: samples covered by a 7 x 7 window of
// samples that is flat at sea level (every height within ±kSeaLevelBand of 0 m) or exactly
// flat at any height (a lake, as SRTM and most DEMs flatten them: max - min <= kLakeFlatness),
// the window lying inside the data; and filled voids that were sea (seaVoids).
//
// Everything is computed from a window of heights around the block with a margin, so texels
// on a block's border come out exactly as the neighbouring block computes them.

#include <cstdint>
#include <memory>
#include <vector>

#include "terralod/build/texel_tile.h"
#include "terralod/core/result.h"
#include "terralod/format/generated_colour.h"

namespace terralod {

class ImageDrape;
class HeightWindows;
class SampleMask;

/// Heights within this of 0 m are at sea level (metres).
constexpr double kSeaLevelBand = 0.5;
/// A window whose heights span no more than this is flat water at any height (metres).
constexpr double kLakeFlatness = 0.01;
/// Half the side of the flat windows that make water (7 x 7 samples).
constexpr int32_t kWaterRadius = 3;

struct SurfaceTexelOptions {
  double spacingX = 1, spacingY = 1;
  /// The data's size in samples: water windows must lie inside it. 0: no limit.
  int32_t columns = 0, rows = 0;
  /// Latitude of every grid row (south first); null or empty: kUnknownLatitude everywhere.
  std::shared_ptr<const std::vector<double>> rowLatitudes;
  /// Voids that were sea (filled since); null: none.
  std::shared_ptr<const SampleMask> seaVoids;
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
  /// The shade layer's texels (one channel, shadeValue) of the square, cells + 1 a side.
  TexelTile shades(int32_t x0, int32_t y0, int32_t cells) const;

 private:
  float height(int32_t gx, int32_t gy) const {
    return mHeights[size_t(gy - mY0) * mSide + size_t(gx - mX0)];
  }
  void generatedColor(int32_t gx, int32_t gy, float* rgb) const;
  float occlusion(int32_t gx, int32_t gy) const;
  bool water(int32_t gx, int32_t gy) const {
    return mWater[size_t(gy - mY0) * mSide + size_t(gx - mX0)] != 0;
  }
  void findWater();

  SurfaceTexelOptions mOptions;
  int32_t mX0 = 0, mY0 = 0, mSide = 0;  // window origin (grid) and side, margin included
  std::vector<float> mHeights;
  std::vector<double> mSums;        // summed-area table of the heights, (side + 1)^2
  std::vector<uint8_t> mWater;      // 1 where the texel is water, side^2 (valid inside the margin)
  std::vector<float> mRowSnowLine;  // the snow line of every window row (metres)
  std::vector<uint8_t> mRowFlags;   // findWater's scratch, kept between blocks
  std::vector<float> mRowMin, mRowMax;
  uint32_t mRefine = 0;  // 0: no image
  int64_t mImageX0 = 0, mImageY0 = 0;
  int32_t mImageSide = 0;
  std::vector<uint8_t> mImage;  // RGBA8 over the block, fine grid
};

}  // namespace terralod
