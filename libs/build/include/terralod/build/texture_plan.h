#pragma once
// How many texels each level's chunk textures get (Ulrich's eq. 5-7). A chunk of level L is
// drawn no closer than D = δ_L·K/τ, where a texel of T metres covers at most T·K/D = T·τ/δ_L
// pixels; texels of T ≤ δ_L/τ_tex therefore never cover more than one pixel while τ ≤ τ_tex.
// The texel count per side is the smallest power of two (plus the shared border texel) that
// achieves it, capped by what the source holds (one texel per DEM sample for normals, per
// image texel for draped colour) and by kMaxTextureSize. Because δ halves as chunks halve,
// the count is the same at every level until the cap bites.

#include <cstdint>
#include <vector>

#include "terralod/build/tree_layout.h"

namespace terralod {

/// Default --min-tau: the τ (pixels) the textures are sized for.
inline constexpr double kDefaultTextureTau = 2.0;

struct TextureLevel {
  uint32_t colorSize = 0, normalSize = 0;   ///< texels per side (2^k + 1)
  uint8_t colorFlags = 0, normalFlags = 0;  ///< kTextureSourceLimited when capped
  /// The level's chunks store no texture and draw their parent's (kNodeInheritsTexture): the
  /// parent level's tiles hold their children's texels unresampled (2 c - 1 texels a side for
  /// children of c, in every layer), so the parent's texture over a child's square is exactly
  /// the child's, stored once instead of twice. Typical where the source's own resolution caps
  /// two or more levels.
  bool inherited = false;
};

/// One entry per level, root first. `colorRefine` = colour texels per DEM cell (image drapes
/// finer than the DEM); `levelError` as in the tileset.
std::vector<TextureLevel> planTextures(const TreeLayout& layout,
                                       const std::vector<double>& levelError, double spacingX,
                                       double spacingY, double textureTau, uint32_t colorRefine);

/// Makes a plan's colour tiles shade tiles (format version 6): half the normal map's texel
/// intervals a side, since the shade only holds water and a soft occlusion term, the colour's
/// detail coming from the normal map and the drawn height (a quarter of the texels; a Zion view
/// differs from the baked colour by 0.58/255 on average, 0.56 with full-resolution shade).
/// Keeps `inherited` only where the halved sizes still nest (2 c - 1).
void halveColourTiles(std::vector<TextureLevel>& plan);

}  // namespace terralod
