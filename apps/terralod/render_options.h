#pragma once
// The options `render` and `bench` share: which tileset, how to select and draw it, and which
// cameras to fly (one view, a flight file or the automatic flight).

#include <CLI/CLI.hpp>
#include <memory>
#include <string>
#include <vector>

#include "terralod/render/terrain_renderer.h"
#include "terralod/render/terrain_scene.h"
#include "terralod/runtime/chunk_tree.h"
#include "terralod/runtime/flight.h"
#include "terralod/runtime/horizon_culling.h"
#include "terralod/runtime/selection.h"

namespace terralod::cli {

struct RenderOptions {
  std::string tileset;
  std::string eye, target;  ///< "X,Y,Z"; both empty: a default overview
  double fovDegrees = 60.0;
  std::string size = "1024x768";
  double tau = 2.0;
  std::string background = "9CC3E6";
  bool wireframe = false, noMorph = false, noSkirts = false, noTextures = false;
  bool chunkBoxes = false;
  bool noBlots = false;         ///< --no-blots: VIPM chunks never drawn as blots
  bool noSuperChunks = false;   ///< --no-super-chunks: every VIPM blot in its own call
  std::string stitch = "auto";  ///< --stitch: VIPM borders, "auto", "flanges" or "fans"
  std::string colorBy = "relief";
  std::string shading = "lit";
  std::vector<double> sun;  ///< azimuth (clockwise from north), elevation; degrees
  double haze = 1.0;        ///< --haze K: aerial perspective strength, 0 off
  std::string flightFile;
  bool autoFlight = false;
  bool climbOnly = false;                               ///< with autoFlight: only its climb
  int frames = 0;                                       ///< 0: the whole flight
  double cacheMB = 512;                                 ///< --cache-mb: chunk memory budget
  HorizonCulling horizonCulling = HorizonCulling::kOn;  ///< --no-horizon-culling: kOff
  std::string vegetation;             ///< --vegetation V.tlv (a path or URL); empty: none
  std::string vegetationWhere;        ///< --vegetation-where RULES
  std::string vegetationMaterials;    ///< --vegetation-materials RASTER (material= rules)
  std::string vegetationPalette;      ///< --vegetation-palette JSON
  double vegetationRange = 0;         ///< --vegetation-range M (0: automatic)
  double vegetationOversampling = 0;  ///< --vegetation-oversampling F (0: the default)
  bool noVegetationTextures = false;  ///< --no-vegetation-textures: LDIs alone, nothing beyond
  bool noVegetationBlend = false;     ///< --no-vegetation-blend: LDIs switch at once (pops)
  bool noVegetationDepth = false;     ///< --no-vegetation-depth: LDIs over the terrain regardless
  bool vegetationReference = false;   ///< --vegetation-reference: ray traced (render), compared
                                      ///< with the warp (bench)
};

/// The share of --cache-mb the vegetation's LDIs and heights get (0 without --vegetation);
/// the chunks get the rest.
inline double vegetationBudgetShare(const RenderOptions& options) {
  return options.vegetation.empty() ? 0.0 : 0.25;
}

/// The scene's options for these command-line options (`complete`: wait for data each frame),
/// drawing with `context`.
SceneOptions sceneOptions(const RenderOptions& options, bool complete, GlContext& context);

/// Registers the shared options on `command`.
void addRenderOptions(CLI::App& command, RenderOptions& options, bool withCamera);

/// The selection options and style the command line asks for (values already validated;
/// the style's stitching depends on the tileset too: stitchFor).
Result<SelectionOptions> selectionOptions(const RenderOptions& options);
Result<TerrainStyle> terrainStyle(const RenderOptions& options);
/// How VIPM borders are stitched on the tileset with `header` (--stitch; auto: fans where the
/// tileset has levels above the 128-cell roots, flanges elsewhere).
VipmStitch stitchFor(const RenderOptions& options, const TilesetHeader& header);

/// Reads and parses a flight file; errors name it.
Result<Flight> readFlightFile(const std::string& path);

/// The cameras to render: the flight file, the automatic flight, or the single view given by
/// --eye/--target (a default overview of the whole tileset without them).
Result<std::vector<Camera>> camerasFor(const RenderOptions& options, const ChunkTree& tree);

}  // namespace terralod::cli
