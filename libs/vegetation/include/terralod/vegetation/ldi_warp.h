#pragma once
// Warping a layered depth image into a view (Shade et al. 1998, §5 of the tiling paper): every
// depth pixel is projected through one matrix (tile frame → clip space, the tile's placement
// and shear on the terrain included) and drawn as a square splat, in McMillan's
// occlusion-compatible order, into a software colour and depth target.
//
// Order. For an orthographic LDI the projection along its rays maps the segment from the eye to
// a point onto the segment from the eye's projection (the epipole) to the point's pixel, so
// anything between the eye and a point lies nearer the epipole in the image. Drawing the pixels
// of each of the four sheets around the epipole from the far edges towards it, and within a
// pixel the layers away from the eye first, draws every point before whatever hides it: back
// to front without sorting. An affine shear keeps segments segments, so the order holds for
// sheared tiles too, with the eye taken into the tile's frame.

#include <cstdint>
#include <optional>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include "terralod/vegetation/ldi.h"
#include "terralod/vegetation/terrain_shear.h"

namespace terralod::veg {

/// Colour (premultiplied RGBA, 0–1) and depth (window depth 0–1, 1 = far) of a picture, row 0
/// at the top.
struct WarpTarget {
  int width = 0, height = 0;
  std::vector<float> rgba;   ///< 4 per pixel, premultiplied
  std::vector<float> depth;  ///< 1 per pixel
  /// Rows [dirtyTop, dirtyBottom) hold everything drawn since the target was clear.
  int dirtyTop = 0, dirtyBottom = 0;

  WarpTarget(int w, int h)
      : width(w),
        height(h),
        rgba(size_t(w) * h * 4, 0.0f),
        depth(size_t(w) * h, 1.0f),
        dirtyTop(h) {}
  /// Clears what was drawn (the dirty rows).
  void clear();
};

/// A target pixel (4 floats, 0–1) as RGBA8, red in the low byte.
uint32_t packRgba8(const float* rgba);

enum class WarpOrder {
  kOcclusionCompatible,  ///< McMillan's sheets (the default)
  kRowMajor,             ///< rows from 0, layers front first: wrong where splats overlap (tests)
};

struct WarpOptions {
  WarpOrder order = WarpOrder::kOcclusionCompatible;
  /// Test against (and write) the target's depth; off, visibility rests on the order alone.
  bool depthTest = true;
  /// Splats cover the projected pixel footprint (at least one pixel, at most maxSplat); off,
  /// every depth pixel is one pixel (magnified LDIs show holes).
  bool sizedSplats = true;
  int maxSplat = 8;
  /// Only the depth pixels over this half of the tile (terrain_shear.h: each half is warped
  /// with its own shear, the far one first).
  std::optional<TileHalf> onlyHalf;
  /// Both halves in one pass: `tileToClip` places the south-east half's depth pixels and this
  /// the north-west half's (for tiles whose two planes differ by less than a pixel, where the
  /// separating plane's order changes nothing the depth test does not mend).
  std::optional<glm::mat4> northWestToClip;
  /// Scales every depth pixel's alpha (a tile fading out).
  float opacity = 1;
};

/// An LDI ready to warp: where each row's layers start (height + 1 offsets into pixels).
struct WarpLdi {
  Ldi ldi;
  std::vector<uint64_t> rowStarts;
  static WarpLdi of(Ldi ldi);
};

struct WarpStats {
  uint64_t depthPixels = 0;  ///< looked at
  uint64_t splats = 0;       ///< drawn (in front of the eye, on the target)
};

/// Draws `ldi` into `target`. `tileToClip` maps the LDI's tile frame to clip space (OpenGL
/// conventions: visible where −w ≤ x, y, z ≤ w); `eyeInTile` is the eye in the tile frame (for
/// the order). Any thread; targets are not shared.
WarpStats warpLdi(const WarpLdi& ldi, const glm::mat4& tileToClip, const glm::vec3& eyeInTile,
                  WarpTarget& target, const WarpOptions& options = {});
/// The same for an LDI not made ready (its row starts are counted first).
WarpStats warpLdi(const Ldi& ldi, const glm::mat4& tileToClip, const glm::vec3& eyeInTile,
                  WarpTarget& target, const WarpOptions& options = {});

}  // namespace terralod::veg
