#pragma once
// Turning a colour image (e.g. a natural-colour satellite scene) into a categorical raster:
// each pixel takes the palette class whose colour is nearest (squared RGB distance; ties go
// to the class listed first). The output is a one-band Byte GeoTIFF (DEFLATE) with the
// image's georeferencing, a colour table holding the palette's colours, and the class names
// as band metadata items CLASS_NAME_<value> inside the TIFF (GeoTIFF cannot hold GDAL's
// category names without a .aux.xml sidecar), so readMaterialRaster() needs no palette for it.
// Pixels the image masks (nodata, alpha 0) become value 255, the output's nodata.
//
// Per-pixel classes are speckled (a bush, a shadow): ClassifyOptions::sievePixels merges
// every 8-connected region smaller than that many pixels into its largest neighbour (GDAL's
// sieve filter, as gdal_sieve.py), the usual minimum mapping unit of a land-cover map. Masked
// pixels are left alone.

#include <cstdint>
#include <string>
#include <vector>

#include "terralod/core/result.h"
#include "terralod/materials/material.h"

namespace terralod {

/// The palette without --palette: broad land-cover colours as seen from orbit.
std::vector<Material> defaultImagePalette();

struct ClassifyImageResult {
  int32_t columns = 0, rows = 0;
  std::vector<uint64_t> counts;  ///< pixels per palette class, in palette order
  uint64_t masked = 0;           ///< pixels the image masks (written as nodata 255)
};

struct ClassifyOptions {
  int32_t sievePixels = 0;  ///< regions smaller than this merge into a neighbour; 0: none
};

/// Classifies the 8-bit RGB image at `imagePath` (bands 1, 2, 3) by `palette` and writes
/// `outputPath` atomically (nothing is left behind on failure). Fails, naming the file, on an
/// unreadable image, fewer than 3 bands, bands that are not 8-bit, an empty palette, or a
/// palette using value 255 when the image has masked pixels.
Result<ClassifyImageResult> classifyImage(const std::string& imagePath,
                                          const std::vector<Material>& palette,
                                          const std::string& outputPath,
                                          const ClassifyOptions& options = {});

}  // namespace terralod
