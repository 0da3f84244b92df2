// terralod vegetation tiling [--size N] [--seed S] [-o FIGURE.png] [--json] [--time N]

#include <chrono>
#include <cstdio>
#include <nlohmann/json.hpp>

#include "commands.h"
#include "terralod/render/image.h"
#include "terralod/vegetation/tiling_statistics.h"
#include "vegetation_commands.h"

namespace terralod::cli {
namespace {

nlohmann::json statsJson(const veg::TileGrid& grid, const veg::Autocorrelation& a) {
  const veg::NeighbourStats n = veg::neighbourStats(grid);
  return {{"prototiles", grid.prototileCount},
          {"same_east", n.sameEast},
          {"same_north", n.sameNorth},
          {"same_expected", n.sameEitherExpected},
          {"with_same_neighbour", n.withSameNeighbour},
          {"with_same_neighbour_expected", n.withSameNeighbourExpected},
          {"largest_clump", n.largestClump},
          {"mean_clump", n.meanClump},
          {"autocorrelation_max_off_origin", a.maxAbsOffOrigin},
          {"autocorrelation_mean_on_axes", a.meanAbsOnAxes},
          {"autocorrelation_mean_off_axes", a.meanAbsOffAxes}};
}

// Lays an n x n tiling by the scanline, then looks every tile up alone; both timed, and
// whether they agree.
void timeTilings(uint32_t n, uint64_t seed) {
  using Clock = std::chrono::steady_clock;
  const auto t0 = Clock::now();
  const veg::LaidTiling laid = veg::scanlineTiling(n, n, seed);
  const auto t1 = Clock::now();
  const veg::WangTiling lookup(n, n, seed);
  uint64_t differ = 0;
  for (uint32_t y = 0; y < n; ++y)
    for (uint32_t x = 0; x < n; ++x) differ += lookup.at(x, y) != laid.at(x, y);
  const auto t2 = Clock::now();
  const bool valid = veg::tilingIsValid(laid);
  std::printf(
      "%ux%u tiles: laid by the scanline in %.2f s (%s), every tile looked up alone in %.2f s "
      "(%.1f ns a tile); %llu tiles differ; stored as seed and size (16 bytes), laid %.1f MB\n",
      n, n, std::chrono::duration<double>(t1 - t0).count(), valid ? "valid" : "INVALID",
      std::chrono::duration<double>(t2 - t1).count(),
      std::chrono::duration<double>(t2 - t1).count() * 1e9 / (double(n) * n),
      (unsigned long long)differ, double(n) * n / 1e6);
}

Image rgbaOf(const veg::RgbImage& rgb) {
  Image image{rgb.width, rgb.height, std::vector<uint8_t>(size_t(rgb.width) * rgb.height * 4, 255)};
  for (size_t i = 0; i < size_t(rgb.width) * rgb.height; ++i)
    for (int c = 0; c < 3; ++c) image.rgba[4 * i + c] = rgb.rgb[3 * i + c];
  return image;
}

}  // namespace

int runVegetationTiling(const VegetationTilingOptions& o) {
  veg::TilingFigureOptions f;
  f.seed = o.seed;
  f.largeTiles = o.size;
  f.maxLag = int(std::min<uint32_t>(16, o.size / 4));
  const veg::TilingFigure figure = veg::tilingFigure(f);
  if (!o.output.empty())
    if (Status s = writeImage(rgbaOf(figure.image), o.output); !s) return fail(s.error().message);
  const nlohmann::json ours =
      statsJson(veg::toGrid(veg::WangTiling(o.size, o.size, o.seed)), figure.ours);
  const nlohmann::json other =
      statsJson(veg::hierarchicalTiling(o.size, o.size, o.seed), figure.comparison);
  if (o.json) {
    std::printf("%s\n", nlohmann::json{{"size", o.size},
                                       {"seed", o.seed},
                                       {"max_lag", f.maxLag},
                                       {"stochastic_wang", ours},
                                       {"robinson_style_hierarchical", other}}
                            .dump(2)
                            .c_str());
    return 0;
  }
  for (const auto& [name, j] : {std::pair{"stochastic Wang (8 prototiles)", ours},
                                std::pair{"Robinson-style hierarchical (16 types)", other}})
    std::printf(
        "%ux%u %s: same prototile east %.4f, north %.4f (chance %.4f); largest clump %llu, "
        "mean %.2f; autocorrelation up to lag %d: max %.4f off the origin, mean %.4f on the "
        "axes, %.4f off them\n",
        o.size, o.size, name, j["same_east"].get<double>(), j["same_north"].get<double>(),
        j["same_expected"].get<double>(), j["largest_clump"].get<unsigned long long>(),
        j["mean_clump"].get<double>(), f.maxLag, j["autocorrelation_max_off_origin"].get<double>(),
        j["autocorrelation_mean_on_axes"].get<double>(),
        j["autocorrelation_mean_off_axes"].get<double>());
  if (!o.output.empty()) std::printf("terralod: wrote %s\n", o.output.c_str());
  if (o.timeSize) timeTilings(o.timeSize, o.seed);
  return 0;
}

}  // namespace terralod::cli
