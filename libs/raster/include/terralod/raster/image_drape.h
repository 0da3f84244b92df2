#pragma once
// An image draped over a DEM: any georeferenced raster GDAL reads (RGB, RGBA or one grey
// band; Byte or wider types, which are stretched to 8 bits), reprojected and resampled by
// GDAL's warper onto the DEM's own grid, refined `refine` times (texel (fx, fy) lies at grid
// point (fx / refine, fy / refine)). The warp is virtual: windows are computed on demand, so
// images of any size drape over DEMs of any size.

#include <cstdint>
#include <memory>
#include <string>

#include "terralod/core/result.h"
#include "terralod/raster/dem_reader.h"

namespace terralod {

class ImageDrape {
 public:
  /// Opens `imagePath` for the DEM described by `dem`. `maxRefine` caps the refinement (a
  /// power of two); the refinement is the largest power of two not above the ratio of the
  /// DEM's spacing to the image's. Fails (naming the image) when it cannot be read, has no
  /// georeferencing, cannot be transformed into the DEM's CRS, or does not overlap the DEM.
  static Result<std::unique_ptr<ImageDrape>> open(const std::string& imagePath, const DemInfo& dem,
                                                  uint32_t maxRefine = 8);
  ~ImageDrape();
  ImageDrape(const ImageDrape&) = delete;
  ImageDrape& operator=(const ImageDrape&) = delete;

  /// The same drape again, for another thread (instances are not thread-safe).
  Result<std::unique_ptr<ImageDrape>> reopen() const;

  uint32_t refine() const { return mRefine; }
  /// Share of the DEM's extent the image covers, 0..1.
  double coverage() const { return mCoverage; }
  const std::string& path() const { return mPath; }

  /// Fine-grid window [x0, x0+w) x [y0, y0+h), south row first, as RGBA8 (alpha 0 where the
  /// image has no data). Points outside the DEM's grid take the nearest grid point's texel.
  Status read(int64_t x0, int64_t y0, int32_t w, int32_t h, uint8_t* rgba) const;

  /// The GDAL handles (image_drape.cpp), reached only through these virtual functions: a
  /// program that never opens a drape then links no GDAL for the ones that hold one
  /// (`terralod-stage`, apps/terralod/CMakeLists.txt).
  struct Impl {
    virtual ~Impl() = default;
    virtual Status read(int64_t x0, int64_t y0, int32_t w, int32_t h, uint8_t* rgba,
                        const std::string& path) const = 0;
  };

 private:
  explicit ImageDrape(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> mImpl;
  std::string mPath;
  uint32_t mRefine = 1;
  double mCoverage = 0;
  DemInfo mDem;
};

}  // namespace terralod
