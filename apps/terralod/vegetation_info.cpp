// terralod vegetation info V.tlv [--json]

#include <cstdio>
#include <nlohmann/json.hpp>
#include <numbers>

#include "commands.h"
#include "terralod/vegetation/tile_placement.h"
#include "terralod/vegetation/vegetation_file.h"
#include "vegetation_commands.h"

namespace terralod::cli {
namespace {

struct RingStats {
  uint64_t ldis = 0, pixels = 0, depthPixels = 0, bytes = 0;
  uint32_t maxLayers = 0;
};

}  // namespace

int runVegetationInfo(const std::string& path, bool json) {
  auto opened = veg::VegetationReader::openPathOrUrl(path);
  if (!opened) return fail(opened.error().message);
  const veg::VegetationReader& r = **opened;
  const veg::VegetationHeader& h = r.header();
  const veg::BakeSettings& s = h.settings;
  std::array<RingStats, veg::kLdiResolutions> rings;
  RingStats total;
  for (int t = 0; t < veg::kPrototiles; ++t)
    for (int res = 0; res < veg::kLdiResolutions; ++res)
      for (int d = 0; d < veg::kLdiDirections; ++d) {
        const veg::LdiEntry& e = r.entry(t, res, d);
        for (RingStats* x : {&rings[res], &total}) {
          x->ldis += 1;
          x->pixels += uint64_t(e.width) * e.height;
          x->depthPixels += e.depthPixels;
          x->bytes += e.bytes;
          x->maxLayers = std::max(x->maxLayers, e.maxLayers);
        }
      }
  nlohmann::json tiles = nlohmann::json::array();
  uint64_t plants = 0, triangles = 0;
  for (int t = 0; t < veg::kPrototiles; ++t) {
    const veg::PrototileContent& c = h.tiles[t];
    uint64_t centred = 0;
    std::array<uint64_t, veg::kSpeciesCount> bySpecies{};
    for (const veg::PlacedObject& o : c.objects)
      if (veg::centredIn(o, s.tileSize)) ++centred, ++bySpecies[size_t(o.species)];
    nlohmann::json species;
    for (int k = 0; k < veg::kSpeciesCount; ++k)
      if (bySpecies[k]) species[std::string(veg::speciesName(veg::Species(k)))] = bySpecies[k];
    tiles.push_back({{"prototile", t},
                     {"edges",
                      {{"north", c.edges.north},
                       {"east", c.edges.east},
                       {"south", c.edges.south},
                       {"west", c.edges.west}}},
                     {"plants", centred},
                     {"stored", c.objects.size()},
                     {"species", species},
                     {"triangles_modelled", h.trianglesModelled[t]}});
    plants += centred;
    triangles += h.trianglesModelled[t];
  }
  nlohmann::json resolutions = nlohmann::json::array();
  for (int res = 0; res < veg::kLdiResolutions; ++res) {
    const RingStats& x = rings[res];
    resolutions.push_back({{"resolution", s.resolutions[res]},
                           {"ring_distance", s.ringDistances[res]},
                           {"elevation_degrees", s.elevations[res] * 180 / std::numbers::pi},
                           {"ldis", x.ldis},
                           {"pixels", x.pixels},
                           {"depth_pixels", x.depthPixels},
                           {"max_layers", x.maxLayers},
                           {"layers_per_pixel", x.pixels ? double(x.depthPixels) / x.pixels : 0.0},
                           {"bytes", x.bytes}});
  }
  if (json) {
    nlohmann::json j = {{"file", path},
                        {"scene", s.scene},
                        {"seed", s.seed},
                        {"tile_size", s.tileSize},
                        {"tile_height", s.tileHeight},
                        {"head_height", s.headHeight},
                        {"rays_per_pixel", s.raysPerPixel},
                        {"bake_seconds", s.bakeSeconds},
                        {"rays_cast", s.raysCast},
                        {"tiles", tiles},
                        {"plants", plants},
                        {"triangles_modelled", triangles},
                        {"ldis", total.ldis},
                        {"pixels", total.pixels},
                        {"depth_pixels", total.depthPixels},
                        {"ldi_bytes", total.bytes},
                        {"file_bytes", r.fileBytes()},
                        {"bytes_per_depth_pixel",
                         total.depthPixels ? double(total.bytes) / total.depthPixels : 0.0},
                        {"resolutions", resolutions}};
    std::printf("%s\n", j.dump(2).c_str());
    return 0;
  }
  std::printf(
      "%s: vegetation scene '%s', seed %llu, %g m tiles, plants up to %.2f m, LDIs for a "
      "viewer %.2f m up\n",
      path.c_str(), s.scene.c_str(), (unsigned long long)s.seed, s.tileSize, s.tileHeight,
      s.headHeight);
  std::printf("tiles: 8 prototiles, %llu plants (%.1f a tile), %.2f M triangles modelled\n",
              (unsigned long long)plants, plants / 8.0, triangles / 1e6);
  for (const auto& t : tiles)
    std::printf("  tile %d  N%d E%d S%d W%d  %3llu plants (%llu stored)  %8llu triangles  %s\n",
                t["prototile"].get<int>(), t["edges"]["north"].get<int>(),
                t["edges"]["east"].get<int>(), t["edges"]["south"].get<int>(),
                t["edges"]["west"].get<int>(), t["plants"].get<unsigned long long>(),
                t["stored"].get<unsigned long long>(),
                t["triangles_modelled"].get<unsigned long long>(), t["species"].dump().c_str());
  std::printf(
      "LDIs: %llu (7 resolutions x 8 directions x 8 tiles), %.1f M pixels, %.1f M depth "
      "pixels, %.1f MB (%.2f bytes a depth pixel); baked in %.1f s, %.1f M rays\n",
      (unsigned long long)total.ldis, total.pixels / 1e6, total.depthPixels / 1e6,
      total.bytes / 1e6, total.depthPixels ? double(total.bytes) / total.depthPixels : 0.0,
      s.bakeSeconds, s.raysCast / 1e6);
  std::printf("  res   ring m  elev deg  pixels    depth px  layers/px  max layers      bytes\n");
  for (int res = 0; res < veg::kLdiResolutions; ++res) {
    const RingStats& x = rings[res];
    std::printf("  %4u  %6.1f  %7.1f  %8llu  %10llu  %9.2f  %10u  %9.1f MB\n", s.resolutions[res],
                s.ringDistances[res], s.elevations[res] * 180 / std::numbers::pi,
                (unsigned long long)x.pixels, (unsigned long long)x.depthPixels,
                x.pixels ? double(x.depthPixels) / x.pixels : 0.0, x.maxLayers, x.bytes / 1e6);
  }
  std::printf("file: %.1f MB\n", r.fileBytes() / 1e6);
  return 0;
}

}  // namespace terralod::cli
