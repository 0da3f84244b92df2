#pragma once
// Writes SyntheticTerrain to a tiled, compressed GeoTIFF without ever holding the whole raster:
// strips of tile rows are generated on all threads and handed to GDAL one at a time. The file
// appears atomically (written beside the target, renamed when complete).

#include <cstdint>
#include <string>

#include "terralod/core/progress.h"
#include "terralod/core/result.h"

namespace terralod {

struct SyntheticDemOptions {
  std::string output;   ///< GeoTIFF to write
  int64_t columns = 0;  ///< raster size in samples, 2..kMaxSyntheticSide each
  int64_t rows = 0;
  uint64_t seed = 1;
  double spacing = 1.0;  ///< metres between samples
  unsigned threads = 0;  ///< 0 = all cores
  /// GeoTIFF compression: "zstd" (default), "deflate", "lzw" or "none".
  std::string compression = "zstd";
};

inline constexpr int64_t kMaxSyntheticSide = 65537;

/// Generates and writes the raster. The CRS is a local Cartesian one in metres whose origin is
/// the south-west corner sample, matching terralod's world coordinates. Fails, leaving nothing
/// behind, on bad options or when the output cannot be written.
Status writeSyntheticDem(const SyntheticDemOptions& options, Progress& progress);

}  // namespace terralod
