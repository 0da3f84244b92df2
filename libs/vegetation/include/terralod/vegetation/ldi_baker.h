#pragma once
// Bakes layered depth images by ray casting with Embree (papers/tiling-layered-depth-images.md
// §4; Shade et al. 1998's stochastic sampling). A prototile's plants stand in a 3×3 context
// of neighbouring tiles (a valid tiling with the prototile in the middle), so plants of the
// neighbours that lean into it are sampled and neighbours shadow and occlude it as they will
// at run time; only surfaces whose footprint is inside the centre tile are kept. Every surface
// a ray passes through is a layer: several jittered rays per pixel, their hits merged within a
// depth tolerance, alpha the share of the pixel's rays that met the layer. Shading is baked:
// sun with a shadow ray, sky light scaled by ambient occlusion from rays over the hemisphere.

#include <cstdint>
#include <memory>
#include <vector>

#include <glm/vec3.hpp>

#include "terralod/vegetation/bake_settings.h"
#include "terralod/vegetation/ldi.h"
#include "terralod/vegetation/plant_library.h"
#include "terralod/vegetation/tile_objects.h"

namespace terralod::veg {

/// A prototile's plants in their context, ready to cast rays at. Thread-safe to query.
class ContextScene {
 public:
  /// `context` gives the prototile of each of the 3×3 tiles, row-major from the south-west;
  /// the middle one is the tile the LDIs are of. Each tile contributes the plants centred in it.
  ContextScene(const std::vector<PrototileContent>& tiles, const std::array<int, 9>& context,
               float tileSize, const PlantLibrary& plants);
  ~ContextScene();
  ContextScene(const ContextScene&) = delete;
  ContextScene& operator=(const ContextScene&) = delete;

  struct Impl;

  /// One LDI; `raysCast` grows by the rays it cast (primary and shading).
  Ldi bake(const LdiCamera& camera, const SamplingSettings& sampling, const Lighting& lighting,
           uint64_t& raysCast) const;

  uint64_t trianglesInCentre() const;  ///< triangles of the plants centred in the middle tile

 private:
  std::unique_ptr<Impl> mImpl;
};

}  // namespace terralod::veg
