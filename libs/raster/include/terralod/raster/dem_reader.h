#pragma once
// Reading elevation rasters through GDAL: every format GDAL reads (GeoTIFF, SRTM .hgt, VTP .bt,
// ESRI ASCII, netCDF, 16-bit PNG, ...) plus RGB-encoded web terrain tiles.
//
// Grid convention used everywhere in terralod: grid column gx = raster column, grid row
// gy = rows - 1 - raster row, so gy grows northwards and (0, 0) is the south-west sample.
// World coordinates are x = gx * spacingX, y = gy * spacingY, z = elevation in metres.

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "terralod/core/result.h"

namespace terralod {

enum class HeightEncoding {
  kPlain,       ///< one band holds heights (scale/offset and vertical units applied)
  kTerrainRgb,  ///< Mapbox: h = (R*65536 + G*256 + B) * 0.1 - 10000
  kTerrarium,   ///< Mapzen:  h = R*256 + G + B/256 - 32768
};

struct DemOpenOptions {
  HeightEncoding encoding = HeightEncoding::kPlain;
  /// With plain heights: the band holding them, 1-based. 0 takes band 1 but refuses a raster of
  /// several 8-bit bands (a photo or an RGB-encoded tile, not heights) and says how to read it.
  int band = 0;
  /// Overrides the horizontal spacing (metres per cell) taken from georeferencing.
  std::optional<std::array<double, 2>> spacing;
  /// Multiplies every height after unit conversion.
  double verticalScale = 1.0;
  /// Rasters whose blocks (GDAL's unit of decoding) need more bytes each are refused at open.
  uint64_t maxBlockBytes = uint64_t{1} << 30;
};

/// What a DEM is, as terralod will use it.
struct DemInfo {
  std::string path;
  int32_t columns = 0;
  int32_t rows = 0;
  double spacingX = 1.0;        ///< metres per cell along x (east)
  double spacingY = 1.0;        ///< metres per cell along y (north)
  std::string spacingSource;    ///< how the spacing was found, for `info` and warnings
  bool spacingAssumed = false;  ///< no usable georeferencing: 1 m was assumed
  double heightScale = 1.0;  ///< applied to raw values: band scale * unit factor * vertical scale
  double heightOffset =
      0.0;  ///< applied after scaling (band offset * unit factor * vertical scale)
  std::optional<double>
      nodata;            ///< raw nodata value of the band, if any (NaN/Inf are always voids)
  std::string dataType;  ///< GDAL type name of the band, e.g. "Int16"
  std::string driver;    ///< GDAL driver short name, e.g. "GTiff"
  std::string crsWkt;    ///< the raster's CRS as WKT (empty when unknown)
  /// The CRS that places the raster on Earth: crsWkt, or WGS 84 when the raster has none and
  /// its bounds are taken as degrees (as its spacing is: spacingSource says so); empty when
  /// its place is unknown.
  std::string earthCrsWkt;
  std::array<double, 6> geoTransform{0, 1, 0, 0, 0, -1};
  bool hasGeoTransform = false;
  bool southUp = false;  ///< raster row 0 is the southern edge (positive geotransform y step)
  HeightEncoding encoding = HeightEncoding::kPlain;
  int bandCount = 1;  ///< bands in the raster
  int band = 1;       ///< the band read as heights (plain encoding)
  /// One 8-bit band and no georeferencing (nor --spacing): more likely a picture than heights.
  bool looksLikeImage = false;
};

/// One open raster. Not thread-safe: each thread that reads needs its own reader (reopen()).
class DemReader {
 public:
  static Result<std::unique_ptr<DemReader>> open(const std::string& path,
                                                 const DemOpenOptions& options);
  ~DemReader();
  DemReader(const DemReader&) = delete;
  DemReader& operator=(const DemReader&) = delete;

  const DemInfo& info() const { return mInfo; }

  /// Opens the same raster again, for another thread.
  Result<std::unique_ptr<DemReader>> reopen() const;

  /// A quick estimate of the height range (min, max) in metres from GDAL's approximate
  /// statistics (overviews or a subsample); it can miss the extremes. Fails if unknown.
  Result<std::array<double, 2>> approximateHeightRange() const;

  /// Latitude (degrees north) of every grid row, south row first, at the raster's centre
  /// column: from the geotransform for a geographic CRS (and for a raster without a CRS whose
  /// bounds look like longitude/latitude, as for its spacing), through PROJ for a projected
  /// one. Empty when the raster's place on Earth is unknown: no georeferencing, a local CRS,
  /// no CRS and bounds that are not degrees, or a transformation PROJ cannot do.
  std::vector<double> gridRowLatitudes() const;

  /// Reads grid window [x0, x0+w) x [y0, y0+h) as heights in metres, south row first,
  /// `w` values per row. Points outside the raster take the value of the nearest raster
  /// sample (edge replication). Voids (nodata, NaN, Inf) come back as NaN.
  Status readWindow(int32_t x0, int32_t y0, int32_t w, int32_t h, float* out) const;

 private:
  struct Impl;
  explicit DemReader(std::unique_ptr<Impl> impl, DemInfo info, DemOpenOptions options);
  std::unique_ptr<Impl> mImpl;
  DemInfo mInfo;
  DemOpenOptions mOptions;
};

/// Caps GDAL's process-wide block cache. terralod streams each raster block once or twice, so
/// a small cache is enough, keeps memory flat, and recycles pages instead of faulting in new
/// ones. Call once at start-up (it is GDAL global state).
void setGdalCacheBytes(uint64_t bytes);

/// Parses "terrain-rgb" / "terrarium" / "none".
std::optional<HeightEncoding> parseHeightEncoding(const std::string& text);

}  // namespace terralod
