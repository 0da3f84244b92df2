#include "render_options.h"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "cli_checks.h"
#include "cli_values.h"
#include "terralod/runtime/overview.h"
#include "terralod/vipm/vipm_fans.h"

namespace terralod::cli {

void addRenderOptions(CLI::App& c, RenderOptions& o, bool withCamera) {
  c.add_option("TILESET", o.tileset,
               "Tileset: a .tlod file, or an http(s):// URL of one (read with range requests)")
      ->required();
  if (withCamera) {
    c.add_option("--eye", o.eye, "Eye position X,Y,Z in world metres (z up)");
    c.add_option("--target", o.target, "Point looked at, X,Y,Z in world metres");
  }
  c.add_option("--fov", o.fovDegrees, "Horizontal field of view in degrees")
      ->capture_default_str()
      ->check(numberBetween(1.0, 179.0));
  c.add_option("--size", o.size, "Image size WIDTHxHEIGHT in pixels")->capture_default_str();
  c.add_option("--tau", o.tau, "Screen-space error bound τ in pixels")
      ->capture_default_str()
      ->check(positiveNumber());
  c.add_option("--background", o.background, "Colour RRGGBB of the empty sky overhead")
      ->capture_default_str();
  c.add_flag("--wireframe", o.wireframe, "Draw triangle edges over the surface");
  c.add_flag("--chunk-boxes", o.chunkBoxes,
             "Outline every drawn chunk's bounding box, coloured by its level");
  c.add_flag("--no-morph", o.noMorph, "Draw every chunk unmorphed (shows the pops morphing hides)");
  c.add_flag("--no-skirts", o.noSkirts,
             "Leave out the skirts, and VIPM chunks' flanges or fans (shows the cracks they hide)");
  c.add_option("--stitch", o.stitch,
               "How VIPM chunks close their borders: flanges (hanging below every border), fans "
               "(border triangles replaced by fans onto both sides' vertices: the same edges on "
               "both sides, nothing below the surface), or auto: fans on tilesets with levels "
               "above the roots (whose nodes close their children's seams, so only fans merge "
               "into them without a pop), flanges on others")
      ->capture_default_str()
      ->check(CLI::IsMember({"auto", "flanges", "fans"}));
  c.add_flag("--no-blots", o.noBlots,
             "VIPM tilesets: draw every chunk one pass per material, also far ones (by default "
             "a chunk where a cell covers less than a pixel is a blot, one pass in its "
             "materials' average colours, which nearer materials fade to)");
  c.add_flag("--no-super-chunks", o.noSuperChunks,
             "VIPM tilesets: draw every blot in its own call (by default the blots of each "
             "super-chunk, 4 x 4 chunks of a level, draw in one)");
  c.add_flag_callback(
      "--no-horizon-culling", [&o] { o.horizonCulling = HorizonCulling::kOff; },
      "Draw every selected chunk, also those nearer terrain hides (culling them never changes "
      "a pixel)");
  c.add_flag("--no-textures", o.noTextures,
             "Ignore the chunks' textures: height tint lit from the drawn geometry (cheaper "
             "where texture filtering is slow, e.g. software OpenGL)");
  c.add_option("--color-by", o.colorBy,
               "Surface colour: relief, level (chunk level), morph, or kind (VIPM leaves green, "
               "roots blue, blots orange, blots drawn with their super-chunk purple; chunked "
               "LOD grey)")
      ->capture_default_str()
      ->check(CLI::IsMember({"relief", "level", "morph", "kind"}));
  c.add_option("--shading", o.shading,
               "lit: the surface colour lit by the sun and the sky; unlit: the colour as it is "
               "(imagery that carries its own light, as a 3D Tiles export of it is drawn)")
      ->capture_default_str()
      ->check(CLI::IsMember({"lit", "unlit"}));
  c.add_option("--sun", o.sun,
               "Sun direction AZ,EL in degrees: azimuth clockwise from north, elevation above "
               "the horizon (default 315,40)")
      ->delimiter(',')
      ->expected(2)
      ->check(finiteNumber());
  c.add_option("--haze", o.haze,
               "Aerial perspective K: scales the haze of the air between the eye and what it "
               "sees (exponential atmosphere; 0 turns it off)")
      ->capture_default_str()
      ->check(nonNegativeNumber());
  c.add_option("--cache-mb", o.cacheMB,
               "Memory budget for chunks in MB (GPU copies and decoded chunks waiting for upload)")
      ->capture_default_str()
      ->check(positiveNumber());
  c.add_option("--vegetation", o.vegetation,
               "Lay a vegetation file's tiles over the terrain (a .tlv path or http(s) URL, "
               "from `terralod vegetation bake`)");
  c.add_option("--vegetation-where", o.vegetationWhere,
               "Where vegetation grows: comma-separated conditions, e.g. "
               "height<2400,slope<30,material=grass|meadow (metres, degrees; materials: a "
               "VIPM tileset's own or --vegetation-materials)");
  c.add_option("--vegetation-materials", o.vegetationMaterials,
               "Categorical raster (any GDAL raster, any CRS) naming the ground's materials "
               "for --vegetation-where material=...; resampled onto the tileset's source grid");
  c.add_option("--vegetation-palette", o.vegetationPalette,
               "JSON palette naming --vegetation-materials' class values (as build --palette)");
  c.add_option("--vegetation-oversampling", o.vegetationOversampling,
               "LDI pixels per screen pixel a vegetation tile is drawn with at least (default "
               "1.25; 1 is the paper's splat size of one: less to warp, plant outlines up to a "
               "pixel fatter)")
      ->check(positiveNumber());
  c.add_option("--vegetation-range", o.vegetationRange,
               "Metres to which vegetation is drawn as LDIs, directional textures beyond "
               "(default: where the coarsest LDI has two pixels a screen pixel)")
      ->check(positiveNumber());
  c.add_flag("--no-vegetation-textures", o.noVegetationTextures,
             "Draw vegetation as LDIs alone: nothing beyond their range (shows where the "
             "directional textures take over)");
  c.add_flag("--no-vegetation-blend", o.noVegetationBlend,
             "Switch a vegetation tile's LDI at once when its resolution or direction changes "
             "instead of blending the two (shows the pops blending hides)");
  c.add_flag("--no-vegetation-depth", o.noVegetationDepth,
             "Composite the vegetation's LDI picture over the terrain without comparing depths "
             "(shows plants behind hills through them: what the depth composite hides)");
  c.add_flag("--vegetation-reference", o.vegetationReference,
             "With --vegetation: ray trace the plants themselves (Embree) as ground truth: "
             "render draws that picture; bench compares its frames with it "
             "(vegetation_ssim_mean, vegetation_coverage_error)");
  c.add_option("--flight", o.flightFile, "Fly the cameras of a flight file (JSON)");
  c.add_flag("--auto-flight", o.autoFlight,
             "Fly the default flight: a low pass across the terrain, then a climb");
  c.add_flag("--climb-only", o.climbOnly,
             "With --auto-flight: fly only its climb (every level merges on the way up)");
  c.add_option("--frames", o.frames, "Frames to fly (default: the whole flight)")
      ->check(wholeNumber<int>(1));
}

Result<SelectionOptions> selectionOptions(const RenderOptions& o) {
  if (!(o.tau > 0) || !std::isfinite(o.tau)) return Error{"--tau must be a positive number"};
  SelectionOptions s;
  s.tau = o.tau;
  s.morph = !o.noMorph;
  return s;
}

SceneOptions sceneOptions(const RenderOptions& o, bool complete, GlContext& context) {
  SceneOptions s;
  s.context = &context;
  s.cacheBytes = uint64_t(o.cacheMB * (1.0 - vegetationBudgetShare(o)) * 1024.0 * 1024.0);
  s.complete = complete;
  s.horizonCulling = o.horizonCulling;
  s.log = [](const std::string& line) {
    std::fprintf(stderr, "terralod: warning: %s\n", line.c_str());
  };
  return s;
}

VipmStitch stitchFor(const RenderOptions& o, const TilesetHeader& header) {
  if (o.stitch == "fans") return VipmStitch::kFans;
  if (o.stitch == "flanges") return VipmStitch::kFlanges;
  const bool upperLevels =
      header.meshKind == MeshKind::kVipm && header.chunkCells(0) > 2 * kStitchLineCells;
  return upperLevels ? VipmStitch::kFans : VipmStitch::kFlanges;
}

Result<TerrainStyle> terrainStyle(const RenderOptions& o) {
  TerrainStyle style;
  auto background = parseColor(o.background, "--background");
  if (!background) return background.error();
  style.background = *background;
  style.wireframe = o.wireframe;
  style.chunkBoxes = o.chunkBoxes;
  style.skirts = !o.noSkirts;
  style.blots = o.noBlots ? VipmBlots::kOff : VipmBlots::kOn;
  style.superChunks = o.noSuperChunks ? VipmSuperChunks::kOff : VipmSuperChunks::kOn;
  style.textures = !o.noTextures;
  if (!o.sun.empty()) {
    if (o.sun.size() != 2 || !std::isfinite(o.sun[0]) || !std::isfinite(o.sun[1]) ||
        o.sun[1] < -90 || o.sun[1] > 90)
      return Error{"--sun must be AZ,EL in degrees with the elevation in [-90, 90]"};
    style.sunAzimuthDegrees = o.sun[0];
    style.sunElevationDegrees = o.sun[1];
  }
  if (!(o.haze >= 0) || !std::isfinite(o.haze)) return Error{"--haze must be 0 or more"};
  style.haze = o.haze;
  style.shading = o.shading == "unlit" ? Shading::kUnlit : Shading::kLit;
  style.colorBy = o.colorBy == "level"   ? ColorBy::kLevel
                  : o.colorBy == "morph" ? ColorBy::kMorph
                  : o.colorBy == "kind"  ? ColorBy::kKind
                                         : ColorBy::kRelief;
  return style;
}

Result<Flight> readFlightFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return makeError(path, "cannot read the flight file");
  std::stringstream text;
  text << in.rdbuf();
  return parseFlight(text.str(), path);
}

Result<std::vector<Camera>> camerasFor(const RenderOptions& o, const ChunkTree& tree) {
  auto size = parseSize(o.size, "--size");
  if (!size) return size.error();
  const int ways = int(!o.flightFile.empty()) + int(o.autoFlight) + int(!o.eye.empty());
  if (ways > 1) return Error{"give one of --flight, --auto-flight or --eye/--target"};
  if (o.climbOnly && !o.autoFlight) return Error{"--climb-only goes with --auto-flight"};
  Flight flight;
  if (!o.flightFile.empty()) {
    auto parsed = readFlightFile(o.flightFile);
    if (!parsed) return parsed.error();
    flight = std::move(parsed).value();
  } else if (o.autoFlight) {
    flight = o.climbOnly ? autoFlightClimb(tree, (*size)[0], (*size)[1], o.fovDegrees, o.frames)
                         : autoFlight(tree, (*size)[0], (*size)[1], o.fovDegrees, o.frames);
  } else {
    Camera c;
    c.width = (*size)[0];
    c.height = (*size)[1];
    c.hfovDegrees = o.fovDegrees;
    if (o.eye.empty() != o.target.empty()) return Error{"--eye and --target go together"};
    if (!o.eye.empty()) {
      auto eye = parsePoint(o.eye, "--eye");
      if (!eye) return eye.error();
      auto target = parsePoint(o.target, "--target");
      if (!target) return target.error();
      c.eye = *eye;
      c.target = *target;
    } else {
      // From the south, 40 degrees down, just far enough to see the whole extent.
      OverviewOptions overview;
      overview.hfovDegrees = c.hfovDegrees;
      overview.width = c.width;
      overview.height = c.height;
      c = overviewCamera(tree.extent(), overview);
    }
    return std::vector<Camera>{c};
  }
  // A file's keyframes are resampled to --frames; the automatic flight was cut to it above.
  if (!o.flightFile.empty() && o.frames > 0) flight.frames = o.frames;
  return flightCameras(flight);
}

}  // namespace terralod::cli
