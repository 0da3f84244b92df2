#pragma once
// Structural similarity of two pictures (Wang, Bovik, Sheikh and Simoncelli 2004, "Image
// quality assessment: from error visibility to structural similarity"), as the vegetation
// figures compare a rendering with its ray-traced truth.

#include <cstdint>
#include <span>

#include "terralod/render/image.h"

namespace terralod {

struct Similarity {
  double mean = 1;    ///< SSIM averaged over the pixels counted
  size_t pixels = 0;  ///< blocks counted
};

/// The block size the comparison first averages over, as the authors' reference
/// implementation does: max(1, round(min(width, height) / 256)) (3 at 1024×768), so SSIM
/// judges the picture at the scale it is seen rather than its pixels' aliasing.
int similarityScale(int width, int height);

/// SSIM of the luma (Rec. 601 weights of the 8-bit channels) of two images of one size, with
/// the paper's constants: averaged over similarityScale() blocks, then an 11×11 Gaussian
/// window of σ 1.5, C1 = (0.01·255)², C2 = (0.03·255)²; the mean over the blocks where
/// `mask` is non-zero for most of their pixels (every block when it is empty; else it holds
/// one byte a pixel, row 0 at the top like the images). `pixels` counts blocks.
Similarity structuralSimilarity(const Image& a, const Image& b, std::span<const uint8_t> mask = {});

}  // namespace terralod
