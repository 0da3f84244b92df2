#pragma once
// The picture a software vegetation renderer paints for a frame (the LDI warp, the field
// tracer), as the render layer that composites it reads it.

#include <cstdint>
#include <span>

namespace terralod::veg {

/// The frame's picture: premultiplied RGBA8 (red in the low byte) and each pixel's distance
/// along the view axis in metres (+infinity where nothing was drawn), row 0 at the top. Only
/// the rows the renderer reports (FrameWarpStats::top..bottom) are written: the rest hold nothing.
struct PictureSpans {
  int width = 0, height = 0;
  std::span<uint32_t> rgba;
  std::span<float> viewDepth;
};

}  // namespace terralod::veg
