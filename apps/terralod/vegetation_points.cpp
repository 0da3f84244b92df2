// terralod vegetation points V.tlv --tiling WxH [--seed S] --csv POINTS.csv --tiles-csv TILES.csv

#include <algorithm>
#include <charconv>
#include <cstdio>
#include <optional>
#include <vector>

#include "commands.h"
#include "terralod/core/atomic_file.h"
#include "terralod/render/image.h"
#include "terralod/vegetation/placement_check.h"
#include "terralod/vegetation/plant_library.h"
#include "terralod/vegetation/tile_placement.h"
#include "terralod/vegetation/vegetation_file.h"
#include "vegetation_commands.h"

namespace terralod::cli {
namespace {

constexpr uint64_t kMaxTilingTiles = uint64_t{1} << 20;  // a million tiles: ~2 GB of CSV at most

Result<std::pair<uint32_t, uint32_t>> parseTiling(const std::string& text) {
  const size_t x = text.find('x');
  uint32_t w = 0, h = 0;
  const char* end = text.data() + text.size();
  if (x == std::string::npos ||
      std::from_chars(text.data(), text.data() + x, w).ptr != text.data() + x ||
      std::from_chars(text.data() + x + 1, end, h).ptr != end || w == 0 || h == 0)
    return makeError("--tiling", "must be WIDTHxHEIGHT in tiles, e.g. 64x64 (got " + text + ")");
  if (uint64_t(w) * h > kMaxTilingTiles)
    return makeError("--tiling",
                     "at most " + std::to_string(kMaxTilingTiles) + " tiles (got " + text + ")");
  return std::pair{w, h};
}

Status writeAndCommit(AtomicFile& file, const std::string& text) {
  if (Status s = file.write(text); !s) return s;
  return file.commit();
}

std::string pointsCsv(const std::vector<veg::TilingPoint>& points) {
  std::string s = "x,y,tight_radius,packing_radius,species,version,tile_x,tile_y\n";
  char line[200];
  for (const veg::TilingPoint& p : points) {
    const veg::PlacedObject& o = *p.object;
    const int n = std::snprintf(line, sizeof line, "%.4f,%.4f,%.4f,%.4f,%s,%u,%u,%u\n", p.x, p.y,
                                o.tightRadius, o.packingRadius,
                                std::string(veg::speciesName(o.species)).c_str(),
                                unsigned(o.version), p.tileX, p.tileY);
    s.append(line, size_t(n));
  }
  return s;
}

std::string tilesCsv(const veg::WangTiling& tiling) {
  std::string s = "tile_x,tile_y,prototile,north,east,south,west\n";
  char line[100];
  for (uint32_t y = 0; y < tiling.height(); ++y)
    for (uint32_t x = 0; x < tiling.width(); ++x) {
      const int k = tiling.at(x, y);
      const veg::TileEdges e = veg::prototileEdges(k);
      const int n = std::snprintf(line, sizeof line, "%u,%u,%d,%d,%d,%d,%d\n", x, y, k, e.north,
                                  e.east, e.south, e.west);
      s.append(line, size_t(n));
    }
  return s;
}

constexpr int kDensityBins = 32;

// A folded density (foldedDensity, kDensityBins a side) as a grey ramp, the tile's edges
// outlined in red.
Image densityPicture(const std::vector<double>& d) {
  constexpr int kBins = kDensityBins, kPixels = 12, kSide = kBins * kPixels;
  Image image{kSide, kSide, std::vector<uint8_t>(size_t(kSide) * kSide * 4, 255)};
  for (int y = 0; y < kSide; ++y)
    for (int x = 0; x < kSide; ++x) {
      const double v = d[size_t(kBins - 1 - y / kPixels) * kBins + x / kPixels];
      const bool edge = x == 0 || y == 0 || x == kSide - 1 || y == kSide - 1;
      uint8_t* p = &image.rgba[(size_t(y) * kSide + x) * 4];
      const uint8_t grey = uint8_t(std::clamp(v * 127.5, 0.0, 255.0));
      p[0] = edge ? 220 : grey;
      p[1] = p[2] = edge ? 40 : grey;
    }
  return image;
}

}  // namespace

void printReport(const veg::PlacementReport& r, const veg::WangTiling& tiling, float tileSize,
                 const std::string& seeds);

int runVegetationPoints(const VegetationPointsOptions& o) {
  auto size = parseTiling(o.tiling);
  if (!size) return fail(size.error().message);
  auto opened = veg::VegetationReader::openPathOrUrl(o.input);
  if (!opened) return fail(opened.error().message);
  const veg::VegetationHeader& h = (*opened)->header();
  const std::vector<veg::PrototileContent> tiles(h.tiles.begin(), h.tiles.end());
  const float tileSize = h.settings.tileSize;
  const veg::WangTiling tiling(size->first, size->second, o.seed);
  const std::vector<veg::TilingPoint> points = veg::tilingPoints(tiles, tileSize, tiling);
  // Every output is opened (and the picture's name checked) before any is written, so a bad
  // path leaves none behind.
  if (!o.densityPng.empty())
    if (auto format = imageFormatFor(o.densityPng); !format) return fail(format.error().message);
  std::optional<AtomicFile> pointsFile, tilesFile;
  for (auto [path, file] :
       {std::pair{&o.pointsCsv, &pointsFile}, std::pair{&o.tilesCsv, &tilesFile}}) {
    if (path->empty()) continue;
    auto created = AtomicFile::create(*path);
    if (!created) return fail(created.error().message);
    file->emplace(std::move(*created));
  }
  if (pointsFile)
    if (Status s = writeAndCommit(*pointsFile, pointsCsv(points)); !s)
      return fail(s.error().message);
  if (tilesFile)
    if (Status s = writeAndCommit(*tilesFile, tilesCsv(tiling)); !s) return fail(s.error().message);
  if (!o.densityPng.empty())
    if (Status s = writeImage(densityPicture(veg::foldedDensity(points, tileSize, kDensityBins)),
                              o.densityPng);
        !s)
      return fail(s.error().message);
  printReport(veg::checkPlacement(tiles, tileSize, tiling), tiling, tileSize,
              std::to_string(o.seed));
  return 0;
}

void printReport(const veg::PlacementReport& r, const veg::WangTiling& tiling, float tileSize,
                 const std::string& seeds) {
  std::printf(
      "terralod: %ux%u tiles of %g m, seed %s: %llu plants; overlaps: tight %llu, packing %llu "
      "(%llu across corners, allowed); closest pair %.3f x tight radii, %.3f x packing radii; "
      "density per m2: interior %.3f, edges %.3f (%.0f%%), corners %.3f (%.0f%%), band %.2f m\n",
      tiling.width(), tiling.height(), tileSize, seeds.c_str(), (unsigned long long)r.objects,
      (unsigned long long)r.tightOverlaps, (unsigned long long)r.packingOverlaps,
      (unsigned long long)r.packingAcrossCorners, r.minTightRatio, r.minPackingRatio,
      r.interiorDensity, r.edgeDensity,
      r.interiorDensity > 0 ? 100 * r.edgeDensity / r.interiorDensity : 0.0, r.cornerDensity,
      r.interiorDensity > 0 ? 100 * r.cornerDensity / r.interiorDensity : 0.0, r.band);
}

int runVegetationPlacement(const VegetationPlacementOptions& o) {
  auto size = parseTiling(o.tiling);
  if (!size) return fail(size.error().message);
  const std::optional<float> tileSize = o.tileSize > 0 ? std::optional(o.tileSize) : std::nullopt;
  veg::PlacementReport sum;
  std::vector<double> density(size_t(kDensityBins) * kDensityBins, 0.0);
  float tileSide = 0;
  for (uint64_t seed = o.seed; seed < o.seed + o.seeds; ++seed) {
    auto scene = veg::vegetationScene(o.scene, tileSize, seed);
    if (!scene) return fail(scene.error().message);
    scene->placement.edgesAndCornersFirst = !o.plain;
    const veg::PlantLibrary plants(seed);
    NullProgress quiet;
    const veg::Placement placed = veg::placeObjects(
        scene->placement, [&](veg::Species s, int v) { return plants.tightRadius(s, v); }, quiet);
    tileSide = scene->placement.tileSize;
    const veg::WangTiling tiling(size->first, size->second, seed);
    const veg::PlacementReport r = veg::checkPlacement(placed.tiles, tileSide, tiling, o.band);
    const std::vector<double> d = veg::foldedDensity(
        veg::tilingPoints(placed.tiles, tileSide, tiling), tileSide, kDensityBins);
    for (size_t i = 0; i < d.size(); ++i) density[i] += d[i] / o.seeds;
    sum.objects += r.objects;
    sum.tightOverlaps += r.tightOverlaps;
    sum.packingOverlaps += r.packingOverlaps;
    sum.packingAcrossCorners += r.packingAcrossCorners;
    sum.tightAcrossCorners += r.tightAcrossCorners;
    sum.minTightRatio =
        seed == o.seed ? r.minTightRatio : std::min(sum.minTightRatio, r.minTightRatio);
    sum.minPackingRatio =
        seed == o.seed ? r.minPackingRatio : std::min(sum.minPackingRatio, r.minPackingRatio);
    sum.band = r.band;  // the scene's largest packing radius: the same for every seed nearly
    sum.interiorDensity += r.interiorDensity / o.seeds;
    sum.edgeDensity += r.edgeDensity / o.seeds;
    sum.cornerDensity += r.cornerDensity / o.seeds;
  }
  if (!o.densityPng.empty())
    if (Status s = writeImage(densityPicture(density), o.densityPng); !s)
      return fail(s.error().message);
  printReport(sum, veg::WangTiling(size->first, size->second, o.seed), tileSide,
              std::to_string(o.seed) + ".." + std::to_string(o.seed + o.seeds - 1));
  return 0;
}

}  // namespace terralod::cli
