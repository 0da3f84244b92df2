#pragma once
// "Blot" drawing of far VIPM chunks (papers/vipm-terrain-story.md): beyond a distance a chunk
// is drawn in one pass with a texture whose texel on each grid point holds the material
// colour there, instead of one pass per material; nearer, the materials fade to their average
// colours, so the switch does not show.
//
// The blot texture is what the chunk's finest level shows with every material at its average
// colour: each grid point takes the colours of the finest triangle over it, weighted by its
// barycentric coordinates (the splat weights interpolate the same way). Colours are encoded
// as the splatting shader encodes its output (linear^(1/2.2)) and blended encoded, as the
// material passes add their weighted, encoded colours: lit by the same light, a blot and its
// faded materials then give the same pixel (but for the haze, which is not a product).
// One texel per grid point of the chunk's unclipped square (cells + 1 a side, as its normal
// map); points outside the data repeat the nearest one inside.

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "terralod/vipm/progressive_mesh.h"

namespace terralod {

/// Linear RGB (0..1) per material index.
using MaterialAverages = std::vector<std::array<float, 3>>;

/// The linear mean of an sRGB image's texels (rgb: 3 bytes a texel).
std::array<float, 3> linearMean(std::span<const uint8_t> rgb);

/// Encoded bytes (RGBA, alpha 255; the shader decodes with ^2.2), (texels + 1)² texels, row 0
/// south, texel (i, j) on grid point (i stride, j stride) (a node above the roots: one texel
/// every stride points, as its normal map). `materials`: per vertex of `mesh`; a material
/// without an average is black.
std::vector<uint8_t> makeBlotTexels(const ProgressiveMesh& mesh, std::span<const uint8_t> materials,
                                    const MaterialAverages& averages, int32_t texels,
                                    int32_t stride = 1);

}  // namespace terralod
