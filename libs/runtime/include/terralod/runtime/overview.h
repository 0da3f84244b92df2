#pragma once
// The default overview: a camera that frames a whole box (a tileset's extent) for a given
// heading, pitch, field of view and image size. Pure: no tileset, no GL.

#include "terralod/runtime/chunk_tree.h"
#include "terralod/runtime/view.h"

namespace terralod {

struct OverviewOptions {
  double headingDegrees =
      0.0;  ///< the way the camera looks, clockwise from north (0: from the south)
  double pitchDegrees = 40.0;  ///< how far it looks down, in (0, 90]
  double hfovDegrees = 60.0;   ///< horizontal field of view
  int width = 1024, height = 768;
  /// The fraction of the image left free on each side of the tighter direction.
  double margin = 0.03;
};

/// The camera looking along `options`' heading and pitch from where all 8 corners of `box` lie
/// inside the view frustum, as close as that allows: the box's corners touch (within the margin)
/// the two sides of the image in the tighter direction and are centred in the other. The target
/// lies on the line of sight, beside the box's centre. Any box, also flat or empty in x or y
/// (the eye then stays a small distance away from it).
Camera overviewCamera(const Box& box, const OverviewOptions& options);

}  // namespace terralod
