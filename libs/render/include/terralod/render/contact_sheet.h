#pragma once
// Many frames on one page: thumbnails in a grid, for looking at a whole flight at a glance.

#include <span>

#include "terralod/render/image.h"

namespace terralod {

/// Scales every frame to `thumbnailWidth` pixels wide (area-averaged) and lays them out left to
/// right, top to bottom, `columns` per row, with a 4-pixel dark gutter. Frames may differ in
/// size; each keeps its aspect. Any thread.
Image makeContactSheet(std::span<const Image> frames, int columns, int thumbnailWidth);

/// `image` scaled to `width` x `height` by averaging the source pixels each target covers.
Image downscale(const Image& image, int width, int height);

}  // namespace terralod
