#include "terralod/vegetation/vegetation_field.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace terralod::veg {

FieldLayout FieldLayout::over(const BakeSettings& settings, double width, double height,
                              std::optional<uint64_t> seed) {
  FieldLayout layout;
  layout.tileSize = settings.tileSize;
  layout.tileHeight = settings.tileHeight;
  layout.resolutions = settings.resolutions;
  const auto tiles = [&](double metres) {
    return uint32_t(std::clamp(std::ceil(metres / settings.tileSize), 1.0, 4.0e9));
  };
  layout.tiling = WangTiling(tiles(width), tiles(height), seed.value_or(settings.seed));
  return layout;
}

double ldiRange(const FieldLayout& layout, const View& view, const FieldOptions& options) {
  if (options.range) return *options.range;
  // A tile w pixels wide on screen at distance d: w = tileSize · K / d.
  const double coarsest = layout.resolutions.back();
  return layout.tileSize * view.pixelsPerRadian * options.rangeOversampling / coarsest;
}

double ldiOpacity(double distance, double range) {
  const double start = range * (1.0 - kRangeFade);
  const double t = std::clamp((distance - start) / (range - start), 0.0, 1.0);
  return 1.0 - t * t * (3.0 - 2.0 * t);
}

int resolutionFor(const FieldLayout& layout, double screenPixels, double pixelsPerScreenPixel) {
  const double wanted = screenPixels * pixelsPerScreenPixel;
  for (int r = kLdiResolutions - 1; r >= 0; --r)
    if (double(layout.resolutions[size_t(r)]) >= wanted) return r;
  return 0;
}

namespace {

// Azimuth clockwise from north of the line of sight from `eye` to `centre`, in 45° sectors
// (direction d looks along d).
double azimuthSectors(const glm::dvec3& eye, const glm::dvec3& centre) {
  return std::atan2(centre.x - eye.x, centre.y - eye.y) / (std::numbers::pi / 4);
}

int wrapDirection(int d) {
  return ((d % kLdiDirections) + kLdiDirections) % kLdiDirections;
}

}  // namespace

int directionFor(const glm::dvec3& eye, const glm::dvec3& centre) {
  return wrapDirection(int(std::lround(azimuthSectors(eye, centre))));
}

void TileDraw::chooseLdis(const FieldLayout& layout, const FieldOptions& options,
                          double wantedPixels, double sectors) {
  resolution = resolutionFor(layout, wantedPixels, 1.0);
  direction = wrapDirection(int(std::lround(sectors)));
  // Resolutions: a pair (finer, coarser) and the coarser one's weight.
  std::array<std::pair<int, float>, 2> byResolution{{{resolution, 1.0f}, {resolution, 0.0f}}};
  int resolutions = 1;
  if (options.blend && resolution + 1 < kLdiResolutions) {
    const double coarser = layout.resolutions[size_t(resolution) + 1];
    // Wanted just above the coarser one's pixels: it still shows, fading out.
    const double t = std::log(wantedPixels / coarser) / std::log(options.resolutionBlend);
    if (t < 1.0) {
      const auto [coarse, fine] = blendOpacities(std::max(0.0, t));
      byResolution = {{{resolution + 1, coarse}, {resolution, fine}}};
      resolutions = 2;
    }
  }
  std::array<std::pair<int, float>, 2> byDirection{{{direction, 1.0f}, {direction, 0.0f}}};
  int directions = 1;
  if (options.blend) {
    // Within directionBlend of the border between this sector and the nearer neighbour.
    const double offset = sectors - std::round(sectors);  // −0.5 … 0.5
    const double fromBorder = 0.5 - std::abs(offset);
    if (fromBorder < options.directionBlend) {
      const int other = wrapDirection(direction + (offset > 0 ? 1 : -1));
      // t: 0 deep in this sector's side of the blend, 1 deep in the other's.
      const double t = 0.5 * (1.0 - fromBorder / options.directionBlend);
      const auto [own, theirs] = blendOpacities(t);
      byDirection = {{{direction, own}, {other, theirs}}};
      // Drawn in one order whichever is nearer: the anticlockwise one first (where two LDIs
      // of one surface overlap, the one drawn last shows; an order that flipped with the
      // nearer direction would swap them at once).
      if (wrapDirection(other + 1) == direction) std::swap(byDirection[0], byDirection[1]);
      directions = 2;
    }
  }
  ldiCount = 0;
  for (int r = 0; r < resolutions; ++r)
    for (int d = 0; d < directions; ++d) {
      const float o = byResolution[size_t(r)].second * byDirection[size_t(d)].second * opacity;
      if (o <= 0.0f) continue;
      ldis[size_t(ldiCount++)] = {byResolution[size_t(r)].first, byDirection[size_t(d)].first, o};
    }
}

namespace {

// Degrees from horizontal of the steeper of the tile's two halves.
double slopeDegrees(const TileOnTerrain& t) {
  double steepest = 0;
  for (TileHalf half : {TileHalf::kSouthEast, TileHalf::kNorthWest}) {
    const glm::mat4 m = halfShear(t, half);
    steepest = std::max(steepest, std::hypot(double(m[0][2]), double(m[1][2])));
  }
  return std::atan(steepest) * 180.0 / std::numbers::pi;
}

}  // namespace

std::vector<TileDraw> selectTiles(const FieldLayout& layout, const View& view,
                                  CornerHeights& heights, const FieldOptions& options,
                                  FieldStats* stats) {
  FieldStats local;
  FieldStats& s = stats ? *stats : local;
  s = {};
  std::vector<TileDraw> draws;
  const double range = ldiRange(layout, view, options);
  const glm::dvec3 eye = view.camera.eye;
  const double size = layout.tileSize;
  const double halfDiagonal = size * std::numbers::sqrt2 / 2;
  // Tiles whose centre may lie within the range (in x and y alone; heights come later).
  const auto first = [&](double v) { return std::max(0.0, std::floor((v - range) / size)); };
  const double x0 = first(eye.x), y0 = first(eye.y);
  const double x1 = std::min(double(layout.tiling.width()) - 1, std::floor((eye.x + range) / size));
  const double y1 =
      std::min(double(layout.tiling.height()) - 1, std::floor((eye.y + range) / size));
  for (double ty = y0; ty <= y1; ++ty) {
    for (double tx = x0; tx <= x1; ++tx) {
      const glm::dvec2 centre{(tx + 0.5) * size, (ty + 0.5) * size};
      if (std::hypot(centre.x - eye.x, centre.y - eye.y) > range + halfDiagonal) continue;
      ++s.considered;
      // Out of the frustum whatever the heights: no chunk is read for it.
      if (!boxInFrustum(view,
                        {{tx * size, ty * size, -1e9}, {(tx + 1) * size, (ty + 1) * size, 1e9}})) {
        ++s.culled;
        continue;
      }
      // The material needs no heights: a tile it refuses reads no chunk either.
      if (!options.where.allowsMaterialAt(centre)) {
        ++s.excluded;
        continue;
      }
      const uint32_t x = uint32_t(tx), y = uint32_t(ty);
      const auto corners = heights.tileCorners(x, y);
      if (!corners) {
        ++s.noHeights;
        continue;
      }
      TileDraw d;
      d.x = x;
      d.y = y;
      d.placement = {glm::vec2(float(tx * size), float(ty * size)), float(size), *corners};
      const auto [low, high] = std::minmax_element(corners->begin(), corners->end());
      const double ground = 0.25 * ((*corners)[0] + (*corners)[1] + (*corners)[2] + (*corners)[3]);
      if (!options.where.allowsGround(ground, slopeDegrees(d.placement))) {
        ++s.excluded;
        continue;
      }
      const glm::dvec3 middle{centre.x, centre.y, ground + 0.5 * layout.tileHeight};
      d.distance = glm::length(middle - eye);
      if (d.distance > range) continue;
      const Box box{{tx * size, ty * size, double(*low)},
                    {(tx + 1) * size, (ty + 1) * size, double(*high) + layout.tileHeight}};
      if (!boxInFrustum(view, box)) {
        ++s.culled;
        continue;
      }
      d.prototile = layout.tiling.at(x, y);
      d.screenPixels = size * view.pixelsPerRadian / std::max(d.distance, 1e-3);
      d.opacity = float(ldiOpacity(d.distance, range));
      if (d.opacity <= 0.0f) continue;
      d.chooseLdis(layout, options, d.screenPixels * options.pixelsPerScreenPixel,
                   azimuthSectors(eye, middle));
      if (d.ldiCount == 0) continue;
      s.blending += d.ldiCount > 1;
      draws.push_back(d);
    }
  }
  std::sort(draws.begin(), draws.end(), [](const TileDraw& a, const TileDraw& b) {
    if (a.distance != b.distance) return a.distance > b.distance;
    return a.y != b.y ? a.y < b.y : a.x < b.x;
  });
  return draws;
}

std::vector<TileDraw> tilesWithin(const FieldLayout& layout, const View& view,
                                  CornerHeights& heights, const VegetationWhere& where,
                                  double maxDistance, double margin) {
  std::vector<TileDraw> tiles;
  const glm::dvec3 eye = view.camera.eye;
  const double size = layout.tileSize;
  const auto clampTile = [](double v, uint32_t count) {
    return std::clamp(std::floor(v), 0.0, double(count) - 1);
  };
  const double x0 = clampTile((eye.x - maxDistance) / size, layout.tiling.width());
  const double x1 = clampTile((eye.x + maxDistance) / size, layout.tiling.width());
  const double y0 = clampTile((eye.y - maxDistance) / size, layout.tiling.height());
  const double y1 = clampTile((eye.y + maxDistance) / size, layout.tiling.height());
  for (double ty = y0; ty <= y1; ++ty)
    for (double tx = x0; tx <= x1; ++tx) {
      const glm::dvec2 centre{(tx + 0.5) * size, (ty + 0.5) * size};
      if (std::hypot(centre.x - eye.x, centre.y - eye.y) > maxDistance) continue;
      const Box grown{{tx * size - margin, ty * size - margin, -1e9},
                      {(tx + 1) * size + margin, (ty + 1) * size + margin, 1e9}};
      if (!boxInFrustum(view, grown) || !where.allowsMaterialAt(centre)) continue;
      const uint32_t x = uint32_t(tx), y = uint32_t(ty);
      const auto corners = heights.tileCorners(x, y);
      if (!corners) continue;
      TileDraw d;
      d.x = x;
      d.y = y;
      d.placement = {glm::vec2(float(tx * size), float(ty * size)), float(size), *corners};
      const auto [low, high] = std::minmax_element(corners->begin(), corners->end());
      const Box box{{tx * size - margin, ty * size - margin, double(*low) - margin},
                    {(tx + 1) * size + margin, (ty + 1) * size + margin,
                     double(*high) + layout.tileHeight + margin}};
      if (!boxInFrustum(view, box)) continue;
      const double ground = 0.25 * ((*corners)[0] + (*corners)[1] + (*corners)[2] + (*corners)[3]);
      if (!where.allowsGround(ground, slopeDegrees(d.placement))) continue;
      d.prototile = layout.tiling.at(x, y);
      d.distance = glm::length(glm::dvec3(centre, ground) - eye);
      tiles.push_back(d);
    }
  return tiles;
}

}  // namespace terralod::veg
