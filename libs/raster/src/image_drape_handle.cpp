// The parts of ImageDrape that hold and call its drape without seeing the GDAL one
// (image_drape.cpp). Compiled on its own, never in a unity unit with that file: where the
// compiler sees the only implementation of ImageDrape::Impl it calls it directly (speculative
// devirtualisation), and a program that holds drapes but never opens one (`terralod-stage`)
// would link GDAL for it.

#include "terralod/raster/image_drape.h"

namespace terralod {

ImageDrape::ImageDrape(std::unique_ptr<Impl> impl) : mImpl(std::move(impl)) {}

ImageDrape::~ImageDrape() = default;

Status ImageDrape::read(int64_t x0, int64_t y0, int32_t w, int32_t h, uint8_t* rgba) const {
  return mImpl->read(x0, y0, w, h, rgba, mPath);
}

}  // namespace terralod
