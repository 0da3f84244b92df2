#pragma once
// Vegetation beyond the LDI range (papers/tiling-layered-depth-images.md §8): the directional
// textures (directional_textures.h) draped on the terrain to the horizon by one full-screen
// pass over the terrain's depth: each pixel's ground point gives its tile (and the tile's
// prototile, from the same Wang tiling as the LDI tiles), its place in the tile, and the line
// of sight's azimuth and elevation, between whose two nearest textures each way it blends.
// It fades in over the last part of the LDI range as the LDI tiles fade out
// (vegetation_field.h), applies the same rules per pixel (height and slope of the ground
// there) and the terrain's haze. Render thread only; needs the terrain's depth readable
// (frame_context.h), else it draws nothing.

#include <cstdint>
#include <memory>

#include "terralod/core/result.h"
#include "terralod/render/composited_layer.h"
#include "terralod/vegetation/directional_textures.h"
#include "terralod/vegetation/vegetation_field.h"

namespace terralod::veg {

class FarVegetationLayer final : public CompositedLayer {
 public:
  /// Compiles the shaders and uploads the textures (with mipmaps).
  static Result<std::unique_ptr<FarVegetationLayer>> create(const DirectionalTextures& textures,
                                                            const FieldLayout& layout,
                                                            const FieldOptions& options);
  ~FarVegetationLayer() override;

  uint32_t draw(const FrameContext& frame) override;
  void setEnabled(bool enabled) { mEnabled = enabled; }
  /// The last frame's pass, to glFinish, milliseconds (0 when nothing was drawn).
  double lastMs() const { return mLastMs; }

 private:
  struct Gl;
  FarVegetationLayer(std::unique_ptr<Gl> gl, const FieldLayout& layout,
                     const FieldOptions& options);
  void recentreWindow(const glm::dvec3& eye);

  std::unique_ptr<Gl> mGl;
  FieldLayout mLayout;
  FieldOptions mOptions;
  bool mEnabled = true;
  double mLastMs = 0;
};

}  // namespace terralod::veg
