#pragma once
// The colour texture of a textured tileset as one image over the data's extent, for
// `terralod export`: assembled from the chunk tiles of the level whose resolution fits, decoded
// from BC1, resampled to the size asked for, and encoded as PNG.

#include <cstdint>
#include <vector>

#include "terralod/core/progress.h"
#include "terralod/format/tileset_reader.h"

namespace terralod {

struct ExportTexture {
  uint32_t width = 0, height = 0;
  /// RGB8, row-major, the northern row first (as images are stored and viewed): pixel (i, j)
  /// covers x ∈ [i, i + 1)·W/width, y ∈ (H − (j + 1)·H/height, H − j·H/height] of the extent
  /// W × H, so texture coordinates (u, v) = (x / W, y / H) (v north) address it as OBJ, PLY and
  /// OpenGL do, and (u, 1 − v) as glTF does.
  std::vector<uint8_t> rgb;
  uint32_t level = 0;      ///< the level whose tiles were sampled
  double levelTexels = 0;  ///< that level's texels across the extent's longer side
};

/// Texels across the data's longer side at the finest level: the most detail the tileset's
/// colour holds. The tileset must be textured.
Result<double> fullTextureResolution(const TilesetReader& tileset);

/// The colour over the data's extent, `longSide` pixels along its longer side and in
/// proportion along the other (at least 1). Samples the coarsest level with at least
/// `longSide` texels across (the finest when none has), bilinearly within each chunk's tile
/// (tiles are edge-aligned, so neighbours agree at their shared border), averaging up to 8x8
/// samples per pixel when the level is finer than the image. Fails on an unreadable chunk or
/// a tile that is not BC1 colour.
Result<ExportTexture> assembleTexture(const TilesetReader& tileset, uint32_t longSide,
                                      Progress& progress);

/// `texture` as an RGB PNG file's bytes.
Result<std::vector<uint8_t>> encodePng(const ExportTexture& texture, const std::string& subject);

}  // namespace terralod
