#pragma once
// `--vegetation-reference`: the vegetation ray traced from the real plant geometry
// (field_tracer.h) in place of the warped LDIs, for render (the picture) and bench (the
// figures: vegetation_ssim_mean/min, vegetation_coverage_error).

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "scene_vegetation.h"
#include "terralod/measure/bench_flight.h"
#include "terralod/render/framebuffer.h"
#include "terralod/vegetation/field_tracer.h"
#include "terralod/vegetation/tileset_corner_heights.h"

namespace terralod::cli {

class VegetationReference {
 public:
  /// Makes the plants of `vegetation`'s file (a few seconds for sunflowers).
  VegetationReference(SceneVegetation& vegetation, TerrainScene& scene);

  /// The painter that traces instead of warping (render --vegetation-reference).
  PictureLayer::Painter painter();

  /// measure() keeps a picture of each frame it measures (drawn | traced | where they
  /// differ) for writePictures.
  void keepPictures() { mKeepPictures = true; }
  /// Writes them as DIR/vegetation_reference_<k>.png (bench --report).
  Status writePictures(const std::string& dir) const;

  /// Draws `view` three ways from the scene's resident chunks (as bench draws it, with the
  /// vegetation traced instead, and bare) and fills the record's vegetationSsim and
  /// vegetationCoverageError (docs/benchmarks.md says how they are counted).
  Status measure(const View& view, TerrainScene& scene, const TerrainStyle& style,
                 const SelectionOptions& selection, FrameRecord& record);

 private:
  PaintedRows trace(const FrameContext& frame, const LayerPicture& picture);

  SceneVegetation& mVegetation;
  veg::FieldTracer mTracer;
  veg::TilesetCornerHeights mHeights;
  std::optional<Framebuffer> mTarget;
  bool mKeepPictures = false;
  std::vector<Image> mPictures;
};

}  // namespace terralod::cli
