#pragma once
// One frame of vegetation in software (papers/tiling-layered-depth-images.md §5.2): the tiles a
// frame draws (vegetation_field.h), back to front, each LDI warped in McMillan's order onto its
// two terrain halves (the far half first, terrain_shear.h) into a colour and depth target. The
// tiles are cut into as many runs of neighbours in that order as there are threads, balanced by
// depth pixels; each thread warps its run into its own target, and the targets are merged
// pixel by pixel, nearer over farther.

#include <cstdint>
#include <span>
#include <vector>

#include "terralod/runtime/view.h"
#include "terralod/vegetation/ldi.h"
#include "terralod/vegetation/ldi_warp.h"
#include "terralod/vegetation/picture_spans.h"
#include "terralod/vegetation/vegetation_field.h"

namespace terralod::veg {

/// Where the LDIs come from (an LdiCache, or a test's own). Called on the frame's thread
/// before the warp starts.
class LdiSource {
 public:
  virtual ~LdiSource() = default;
  /// A frame starts: what ldi() returns from here on stays valid until the next call.
  virtual void beginFrame() {}
  /// The LDI, or nullptr when it is not at hand (the tile is left out this frame).
  virtual const WarpLdi* ldi(int prototile, int resolution, int direction) = 0;
  /// Its depth pixels (for balancing threads) without reading it.
  virtual uint64_t depthPixels(int prototile, int resolution, int direction) const = 0;
};

struct FrameWarpOptions {
  unsigned threads = 1;
  WarpOptions warp;  ///< per LDI (its onlyHalf and northWestToClip are set per tile)
  /// Warp a tile's halves in one pass when their planes part by less than this many screen
  /// pixels at the tile's corners (0: always two passes, the far half first).
  double onePassTwistPixels = 0.5;
};

struct FrameWarpStats {
  uint32_t tiles = 0;         ///< tiles warped
  uint32_t ldis = 0;          ///< LDIs warped (more than tiles where tiles blend two or four)
  uint32_t missingLdis = 0;   ///< tiles missing an LDI that was not at hand
  uint32_t onePassTiles = 0;  ///< LDIs whose tile's halves were warped in one pass
  uint64_t depthPixels = 0;
  uint64_t splats = 0;
  double warpMs = 0;        ///< warping (all threads, wall)
  double mergeMs = 0;       ///< merging the threads' targets into the picture
  int top = 0, bottom = 0;  ///< the picture's rows [top, bottom) were written
};

/// Keeps the per-thread targets between frames.
class FrameWarper {
 public:
  FrameWarpStats warp(std::span<const TileDraw> tiles, LdiSource& ldis, const View& view,
                      const FrameWarpOptions& options, const PictureSpans& out);

 private:
  std::vector<WarpTarget> mTargets;
};

/// The matrices one tile half is warped with: tile frame → clip space of `view` (a finite
/// perspective whose window depth frameDepthToDistance turns back into metres) and the eye in
/// the tile frame.
struct HalfTransform {
  glm::mat4 tileToClip;
  glm::vec3 eyeInTile;
};
HalfTransform halfTransform(const View& view, const TileOnTerrain& tile, TileHalf half,
                            double farPlane);
/// Metres along the view axis of a window depth (0–1) written with halfTransform's matrices.
float frameDepthToDistance(float windowDepth, double farPlane);

}  // namespace terralod::veg
