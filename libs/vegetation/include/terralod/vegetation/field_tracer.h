#pragma once
// Ground truth for vegetation over a terrain (`--vegetation-reference`): the plants of every
// tile the caller lists, made again from the .tlv's placement and seed, each tile's plants
// placed by the same shear as the LDI warp (terrain_shear.h: a point takes the shear of the
// half of its tile it lies over), ray traced with Embree from a view and lit as the baker
// lit the LDIs (sun with a shadow ray, sky light scaled by ambient occlusion). Its picture is
// what the warped LDIs stand for, for the same camera: the figures compare the two.

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "terralod/runtime/view.h"
#include "terralod/vegetation/bake_settings.h"
#include "terralod/vegetation/picture_spans.h"
#include "terralod/vegetation/plant_library.h"
#include "terralod/vegetation/terrain_shear.h"
#include "terralod/vegetation/vegetation_file.h"

namespace terralod::veg {

/// A tile of the field as the tracer places it.
struct TracedTile {
  TileOnTerrain placement;
  int prototile = 0;
};

struct TraceOptions {
  uint32_t raysPerPixel = 4;  ///< a square number: stratified jitter; alpha is the share hit
  Lighting lighting;          ///< the baker's
  unsigned threads = 1;
};

struct TraceStats {
  uint64_t rays = 0;  ///< primary and shading rays
  double ms = 0;
  int top = 0, bottom = 0;  ///< rows written: every one
};

class FieldTracer {
 public:
  /// Makes each prototile's plants (those centred in it) as one mesh, the 8 as Embree scenes.
  FieldTracer(const VegetationHeader& header, const PlantLibrary& plants);
  ~FieldTracer();
  FieldTracer(const FieldTracer&) = delete;
  FieldTracer& operator=(const FieldTracer&) = delete;

  /// The tiles to trace (each an instance per half), replacing the last ones.
  void setTiles(std::span<const TracedTile> tiles);

  /// Paints `view` into `out` (premultiplied sRGB RGBA8 and view-axis depth, as the LDI warp
  /// does); rays stop at `terrainViewDepth` (per pixel, metres along the view axis, row 0 at
  /// the top; +infinity: nothing there).
  TraceStats trace(const View& view, std::span<const float> terrainViewDepth,
                   const PictureSpans& out, const TraceOptions& options) const;

  uint64_t triangles() const;  ///< of the 8 prototile meshes

  struct Impl;

 private:
  std::unique_ptr<Impl> mImpl;
};

}  // namespace terralod::veg
