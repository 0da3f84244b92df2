#pragma once
// Which vegetation tiles a frame draws, and how (papers/tiling-layered-depth-images.md §5.1–5.2):
// the Wang tiling laid over the terrain from its south-west sample, each tile standing on the
// terrain by its four corner heights (terrain_shear.h) where the rules allow it
// (vegetation_where.h); for a view, the tiles in the frustum within the LDI range, back to
// front, each with the resolution whose pixels come closest to the screen's (the rings) and the
// view direction nearest the line from the eye to it. Pure: heights come from the caller.

#include <array>
#include <cstdint>
#include <optional>
#include <utility>
#include <vector>

#include <glm/vec3.hpp>

#include "terralod/runtime/view.h"
#include "terralod/vegetation/terrain_shear.h"
#include "terralod/vegetation/vegetation_file.h"
#include "terralod/vegetation/vegetation_where.h"
#include "terralod/vegetation/wang_tiling.h"

namespace terralod::veg {

/// The tiling over a terrain: tile (x, y) covers [x·s, (x+1)·s] × [y·s, (y+1)·s] metres from the
/// terrain's south-west sample, s the .tlv's tile size.
struct FieldLayout {
  float tileSize = 4;
  float tileHeight = 2;  ///< metres: the tallest plant (bounding boxes)
  std::array<uint32_t, kLdiResolutions> resolutions{};  ///< LDI pixels across, finest first
  WangTiling tiling{1, 1, 0};                           ///< covers the terrain's extent

  /// From a .tlv's settings over a terrain `width` × `height` metres; the tiling's seed is the
  /// file's unless `seed` is given.
  static FieldLayout over(const BakeSettings& settings, double width, double height,
                          std::optional<uint64_t> seed = {});
};

/// The terrain under the tiles: a tile's four corner heights (SW, SE, NE, NW), or nothing
/// where there is no terrain (outside the data) or the heights are not at hand yet.
class CornerHeights {
 public:
  virtual ~CornerHeights() = default;
  virtual std::optional<std::array<float, 4>> tileCorners(uint32_t x, uint32_t y) = 0;
};

struct FieldOptions {
  VegetationWhere where;
  /// LDI pixels per screen pixel at which a tile switches to the next finer resolution (1: the
  /// paper's "splat size of one"). Splats are whole pixels, rounded up so that no hole opens
  /// between them: at 1 a plant's outline grows by up to a pixel where its splats reach two;
  /// 1.25 keeps most splats at one pixel (docs/benchmarks.md: the coverage error against the
  /// traced truth 5.1 % → 4.8 % on the low flight, for about a fifth more warp).
  double pixelsPerScreenPixel = 1.25;
  /// The LDI range: tiles are drawn as LDIs while the coarsest resolution has at most this
  /// many LDI pixels per screen pixel; farther ones are left to the directional textures.
  double rangeOversampling = 2.0;
  /// The LDI range in metres instead (a user's trade of speed for parallax).
  std::optional<double> range;
  /// Blend between two LDIs instead of switching at once: between resolutions while a tile's
  /// wanted resolution is within `resolutionBlend` times the coarser one's (the coarser one
  /// fading out as the finer fades in), and between directions within `directionBlend` of the
  /// 45° sectors' borders (a fraction of a sector). Off: every tile shows one LDI.
  bool blend = true;
  double resolutionBlend = 1.15;
  double directionBlend = 0.1;
};

/// One LDI a tile draws and how much of it (blends draw two or four).
struct TileLdi {
  int resolution = 0;  ///< index into FieldLayout::resolutions (the ring)
  int direction = 0;   ///< 0–7: the LDI looking along azimuth 45°·direction (0: north)
  float opacity = 1;
  bool operator==(const TileLdi&) const = default;
};

/// How the two members of a blend at weight t (0: the first alone, 1: the second alone) are
/// drawn: each fully opaque over the middle half, fading over its own end's half, so that no
/// pixel of a surface both show turns transparent and neither appears or goes at once.
inline std::pair<float, float> blendOpacities(double t) {
  return {float(std::min(1.0, 2.0 * (1.0 - t))), float(std::min(1.0, 2.0 * t))};
}

/// The far part of the LDI range, as a fraction of it, over which LDI tiles fade out and the
/// directional textures (far_vegetation_layer.h) fade in: no tile leaves the picture at once.
inline constexpr double kRangeFade = 0.2;

/// How much of an LDI tile at `distance` is drawn: 1 until the fade begins, 0 at `range`
/// (the textures' weight is the rest, smoothstep in between).
double ldiOpacity(double distance, double range);

/// One tile of a frame.
struct TileDraw {
  uint32_t x = 0, y = 0;  ///< tile column and row
  int prototile = 0;
  int resolution = 0;             ///< the nearest resolution (the ring)
  int direction = 0;              ///< the nearest direction
  std::array<TileLdi, 4> ldis{};  ///< what it draws: ldiCount of them
  int ldiCount = 0;
  TileOnTerrain placement;
  double distance = 0;      ///< metres from the eye to the tile's centre
  double screenPixels = 0;  ///< the tile's width on screen
  float opacity = 1;        ///< ldiOpacity(): fading out towards the range's end (the ldis'
                            ///< opacities include it)
  /// The tile's LDIs as chosen: one with blending off, else up to two resolutions × two
  /// directions. `stats` counts the blends.
  void chooseLdis(const FieldLayout& layout, const FieldOptions& options, double wantedPixels,
                  double azimuthSectors);
};

struct FieldStats {
  uint32_t considered = 0;  ///< tiles within the range around the eye
  uint32_t blending = 0;    ///< of those drawn: tiles drawing more than one LDI
  uint32_t noHeights = 0;   ///< of those: no terrain under them (or not at hand)
  uint32_t excluded = 0;    ///< refused by the rules
  uint32_t culled = 0;      ///< outside the frustum
};

/// The LDI range for `view`: the distance at which a tile is as wide on screen as the coarsest
/// LDI's pixels divided by the oversampling (or the options' range when given).
double ldiRange(const FieldLayout& layout, const View& view, const FieldOptions& options);

/// The resolution index for a tile `screenPixels` wide: the coarsest with at least
/// screenPixels · pixelsPerScreenPixel pixels (the finest when none has).
int resolutionFor(const FieldLayout& layout, double screenPixels, double pixelsPerScreenPixel);

/// The direction index for looking from `eye` at a tile centred at `centre`.
int directionFor(const glm::dvec3& eye, const glm::dvec3& centre);

/// The tiles `view` draws as LDIs, farthest first.
std::vector<TileDraw> selectTiles(const FieldLayout& layout, const View& view,
                                  CornerHeights& heights, const FieldOptions& options,
                                  FieldStats* stats = nullptr);

/// Every tile the rules allow within `maxDistance` of the eye (tile centre) whose box, grown by
/// `margin` metres, meets the frustum; no LOD, no order (the ground truth traces them all).
std::vector<TileDraw> tilesWithin(const FieldLayout& layout, const View& view,
                                  CornerHeights& heights, const VegetationWhere& where,
                                  double maxDistance, double margin);

}  // namespace terralod::veg
