#pragma once
// The `terralod vegetation` subcommands (cmd_vegetation.cpp registers them).

#include <string>

#include "terralod/vegetation/vegetation_scenes.h"

namespace terralod::cli {

struct VegetationBakeOptions {
  std::string scene = "sunflowers", output;
  float tileSize = 0;  ///< 0: the scene's own
  uint64_t seed = 1;
  unsigned threads = 0;  ///< 0: all cores
  uint32_t finest = 0;   ///< finest LDI resolution (0: the paper's 468); the rest scale with it
  uint32_t raysPerPixel = 4, occlusionRays = 8;
};
int runVegetationBake(const VegetationBakeOptions& options);

int runVegetationInfo(const std::string& path, bool json);

struct VegetationPointsOptions {
  std::string input, tiling = "64x64", pointsCsv, tilesCsv, densityPng;
  uint64_t seed = 1;
};
int runVegetationPoints(const VegetationPointsOptions& options);

struct VegetationPlacementOptions {
  std::string scene = "sunflowers", tiling = "64x64", densityPng;
  float tileSize = 0;
  uint64_t seed = 1;
  uint32_t seeds = 1;
  bool plain = false;  ///< the paper's plain round-robin (no edges and corners first)
  double band = 0;     ///< metres (0: twice the largest packing radius)
};
int runVegetationPlacement(const VegetationPlacementOptions& options);

struct VegetationTilingOptions {
  uint32_t size = 256;  ///< tiles a side of the large tilings measured
  uint64_t seed = 1;
  std::string output;  ///< the Figure-4 comparison picture (PNG), if given
  bool json = false;
  uint32_t timeSize = 0;  ///< also lay and look up a tiling this many tiles a side, timed
};
int runVegetationTiling(const VegetationTilingOptions& options);

struct RenderTileOptions {
  std::string input, output, view = "ldi";  ///< ldi | top
  std::string tile = "0";                   ///< 0..7 or all (a sheet of the 8)
  int resolution = 0, direction = 0;
};
int runVegetationRenderTile(const RenderTileOptions& options);

}  // namespace terralod::cli
