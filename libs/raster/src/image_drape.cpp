#include "terralod/raster/image_drape.h"

#include <gdal_priv.h>
#include <gdal_utils.h>
#include <ogr_spatialref.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <vector>

#include "gdal_support.h"

namespace terralod {

namespace {

struct GdalDrape final : ImageDrape::Impl {
  GDALDatasetH source = nullptr;
  GDALDatasetH expanded = nullptr;  // a paletted image as RGBA (virtual), warped instead
  GDALDatasetH warped = nullptr;
  int colorBands = 3;  // 3: RGB from bands 1-3; 1: grey from band 1
  int alphaBand = 0;   // band of the warped dataset holding its alpha
  bool wide = false;   // not Byte: stretched from [lo, hi]
  double lo = 0, hi = 255;
  int64_t width = 0, height = 0;  // of the fine grid
  ~GdalDrape() override {
    if (warped) GDALClose(warped);
    if (expanded) GDALClose(expanded);
    if (source) GDALClose(source);
  }
  Status read(int64_t x0, int64_t y0, int32_t w, int32_t h, uint8_t* rgba,
              const std::string& path) const override;
};

struct Bounds {
  double x0 = std::numeric_limits<double>::infinity(), y0 = x0, x1 = -x0, y1 = -x0;
  void add(double x, double y) {
    x0 = std::min(x0, x);
    x1 = std::max(x1, x);
    y0 = std::min(y0, y);
    y1 = std::max(y1, y);
  }
  double area() const { return x1 > x0 && y1 > y0 ? (x1 - x0) * (y1 - y0) : 0.0; }
};

Result<std::unique_ptr<GdalDrape>> openDrape(const std::string& path, const DemInfo& dem,
                                             uint32_t maxRefine, uint32_t& refine,
                                             double& coverage) {
  gdal::ensureRegistered();
  gdal::QuietErrors quiet;
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) return makeError(path, "no such file");
  auto impl = std::make_unique<GdalDrape>();
  impl->source =
      GDALOpenEx(path.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY, nullptr, nullptr, nullptr);
  if (!impl->source) {
    const std::string why = gdal::lastErrorMessage();
    return makeError(
        path, "cannot be read as an image" +
                  (why.empty() ? std::string(" (not a raster format GDAL knows)") : ": " + why));
  }
  GDALDataset* src = GDALDataset::FromHandle(impl->source);
  int bands = src->GetRasterCount();
  if (bands < 1) return makeError(path, "has no raster bands");
  GDALDatasetH warpInput = impl->source;
  if (src->GetRasterBand(1)->GetColorTable()) {
    // Palette indices are not colours: expand them to RGBA first (a virtual dataset).
    char expandArgs[3][16] = {"-of", "VRT", "-expand"};
    char rgba[] = "rgba";
    char* argv[] = {expandArgs[0], expandArgs[1], expandArgs[2], rgba, nullptr};
    GDALTranslateOptions* options = GDALTranslateOptionsNew(argv, nullptr);
    int usageError = 0;
    impl->expanded = GDALTranslate("", impl->source, options, &usageError);
    GDALTranslateOptionsFree(options);
    if (!impl->expanded) return makeError(path, "has a colour palette GDAL cannot expand");
    warpInput = impl->expanded;
    bands = 3;
  }
  impl->colorBands = bands >= 3 ? 3 : 1;
  double gt[6];
  if (src->GetGeoTransform(gt) != CE_None)
    return makeError(path, "has no georeferencing, so it cannot be placed on the DEM");
  if (!dem.hasGeoTransform)
    return makeError(path, "cannot be placed: the DEM " +
                               std::filesystem::path(dem.path).filename().string() +
                               " has no georeferencing");
  const std::string imageWkt = src->GetProjectionRef() ? src->GetProjectionRef() : "";
  if (imageWkt.empty() != dem.crsWkt.empty())
    return makeError(path, imageWkt.empty() ? "has no coordinate system (the DEM has one)"
                                            : "has a coordinate system but the DEM has none");

  // The image's outline in the DEM's CRS, for the overlap and the image's resolution there.
  const int cols = src->GetRasterXSize(), rows = src->GetRasterYSize();
  std::unique_ptr<OGRCoordinateTransformation> transform;
  if (!imageWkt.empty()) {
    OGRSpatialReference from, to;
    if (from.importFromWkt(imageWkt.c_str()) != OGRERR_NONE ||
        to.importFromWkt(dem.crsWkt.c_str()) != OGRERR_NONE)
      return makeError(path, "has a coordinate system GDAL cannot read");
    from.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
    to.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
    transform.reset(OGRCreateCoordinateTransformation(&from, &to));
    if (!transform)
      return makeError(path, "cannot be transformed from its coordinate system to the DEM's");
  }
  Bounds image;
  constexpr int kSteps = 20;
  for (int side = 0; side < 4; ++side)
    for (int i = 0; i <= kSteps; ++i) {
      const double t = double(i) / kSteps;
      const double px = side == 0 ? t * cols : side == 1 ? cols : side == 2 ? (1 - t) * cols : 0;
      const double py = side == 0 ? 0 : side == 1 ? t * rows : side == 2 ? rows : (1 - t) * rows;
      double x = gt[0] + px * gt[1] + py * gt[2], y = gt[3] + px * gt[4] + py * gt[5];
      if (transform && !transform->Transform(1, &x, &y)) continue;
      if (std::isfinite(x) && std::isfinite(y)) image.add(x, y);
    }
  if (image.area() == 0)
    return makeError(path, "cannot be transformed from its coordinate system to the DEM's");
  const auto& dg = dem.geoTransform;
  Bounds demBounds;
  demBounds.add(dg[0], dg[3]);
  demBounds.add(dg[0] + dem.columns * dg[1], dg[3] + dem.rows * dg[5]);
  Bounds overlap;
  overlap.add(std::max(image.x0, demBounds.x0), std::max(image.y0, demBounds.y0));
  overlap.add(std::min(image.x1, demBounds.x1), std::min(image.y1, demBounds.y1));
  if (image.x0 >= demBounds.x1 || image.x1 <= demBounds.x0 || image.y0 >= demBounds.y1 ||
      image.y1 <= demBounds.y0 || overlap.area() == 0)
    return makeError(
        path, "does not overlap the DEM " + std::filesystem::path(dem.path).filename().string());
  coverage = overlap.area() / demBounds.area();

  if (refine == 0) {
    const double imagePixel = std::sqrt(image.area() / (double(cols) * rows));
    const double demPixel = std::sqrt(std::abs(dg[1] * dg[5]));
    refine = 1;
    while (refine * 2 <= maxRefine && demPixel / imagePixel >= refine * 2 * 0.95) refine *= 2;
  }
  const double r = refine;
  const double px = dg[1] / r, py = dg[5] / r;
  const double ox = dg[0] + 0.5 * dg[1] - 0.5 * px, oy = dg[3] + 0.5 * dg[5] - 0.5 * py;
  impl->width = int64_t(dem.columns - 1) * refine + 1;
  impl->height = int64_t(dem.rows - 1) * refine + 1;
  const double yA = oy, yB = oy + double(impl->height) * py;
  const auto num = gdal::exactNumber;
  const double imageToFine =
      std::sqrt(image.area() / (double(cols) * rows)) / std::sqrt(std::abs(px * py));
  std::vector<std::string> args = {"-of",
                                   "VRT",
                                   "-te",
                                   num(ox),
                                   num(std::min(yA, yB)),
                                   num(ox + double(impl->width) * px),
                                   num(std::max(yA, yB)),
                                   "-ts",
                                   std::to_string(impl->width),
                                   std::to_string(impl->height),
                                   "-r",
                                   imageToFine < 0.75 ? "average" : "bilinear",
                                   "-dstalpha",
                                   "-wo",
                                   "DST_ALPHA_MAX=255"};
  if (!dem.crsWkt.empty()) {
    args.insert(args.end(), {"-t_srs", dem.crsWkt});
  }
  impl->warped = gdal::warp(warpInput, std::move(args)).release();
  if (!impl->warped) {
    const std::string why = gdal::lastErrorMessage();
    return makeError(path, "cannot be reprojected onto the DEM" + (why.empty() ? "" : ": " + why));
  }
  impl->alphaBand = GDALGetRasterCount(impl->warped);
  GDALRasterBandH first = GDALGetRasterBand(warpInput, 1);
  if (GDALGetRasterDataType(first) != GDT_Byte) {
    impl->wide = true;
    impl->lo = std::numeric_limits<double>::infinity();
    impl->hi = -impl->lo;
    for (int b = 1; b <= impl->colorBands; ++b) {
      double mm[2];
      if (GDALComputeRasterMinMax(GDALGetRasterBand(warpInput, b), TRUE, mm) != CE_None)
        return makeError(path, "cannot compute the value range of band " + std::to_string(b));
      impl->lo = std::min(impl->lo, mm[0]);
      impl->hi = std::max(impl->hi, mm[1]);
    }
    if (!(impl->hi > impl->lo)) impl->hi = impl->lo + 1;
  }
  return impl;
}

}  // namespace

Result<std::unique_ptr<ImageDrape>> ImageDrape::open(const std::string& imagePath,
                                                     const DemInfo& dem, uint32_t maxRefine) {
  uint32_t refine = 0;
  double coverage = 0;
  auto impl = openDrape(imagePath, dem, std::max(1u, maxRefine), refine, coverage);
  if (!impl) return impl.error();
  std::unique_ptr<ImageDrape> d(new ImageDrape(std::move(impl).value()));
  d->mPath = imagePath;
  d->mRefine = refine;
  d->mCoverage = coverage;
  d->mDem = dem;
  return d;
}

Result<std::unique_ptr<ImageDrape>> ImageDrape::reopen() const {
  uint32_t refine = mRefine;
  double coverage = 0;
  auto impl = openDrape(mPath, mDem, mRefine, refine, coverage);
  if (!impl) return impl.error();
  std::unique_ptr<ImageDrape> d(new ImageDrape(std::move(impl).value()));
  d->mPath = mPath;
  d->mRefine = mRefine;
  d->mCoverage = mCoverage;
  d->mDem = mDem;
  return d;
}

Status GdalDrape::read(int64_t x0, int64_t y0, int32_t w, int32_t h, uint8_t* rgba,
                       const std::string& path) const {
  gdal::QuietErrors quiet;
  const GdalDrape& m = *this;
  const int64_t cx0 = std::clamp<int64_t>(x0, 0, m.width - 1),
                cx1 = std::clamp<int64_t>(x0 + w - 1, 0, m.width - 1);
  const int64_t cy0 = std::clamp<int64_t>(y0, 0, m.height - 1),
                cy1 = std::clamp<int64_t>(y0 + h - 1, 0, m.height - 1);
  const int rw = int(cx1 - cx0 + 1), rh = int(cy1 - cy0 + 1);
  // Grid y grows northwards; the warped raster is north-up.
  const int64_t row0 = m.height - 1 - cy1;
  std::vector<float> values(size_t(rw) * rh * 4);
  int bandList[4] = {1, m.colorBands == 3 ? 2 : 1, m.colorBands == 3 ? 3 : 1, m.alphaBand};
  if (GDALDatasetRasterIO(m.warped, GF_Read, int(cx0), int(row0), rw, rh, values.data(), rw, rh,
                          GDT_Float32, 4, bandList, 4 * sizeof(float),
                          int64_t(rw) * 4 * sizeof(float), sizeof(float)) != CE_None) {
    const std::string why = gdal::lastErrorMessage();
    return makeError(path, "read failed" + (why.empty() ? "" : ": " + why));
  }
  const double scale = m.wide ? 255.0 / (m.hi - m.lo) : 1.0, offset = m.wide ? m.lo : 0.0;
  for (int32_t y = 0; y < h; ++y) {
    const int64_t gy = std::clamp<int64_t>(y0 + y, cy0, cy1);
    const float* row = values.data() + size_t(cy1 - gy) * rw * 4;
    uint8_t* out = rgba + size_t(y) * w * 4;
    for (int32_t x = 0; x < w; ++x) {
      const int64_t gx = std::clamp<int64_t>(x0 + x, cx0, cx1);
      const float* v = row + size_t(gx - cx0) * 4;
      for (int c = 0; c < 3; ++c)
        out[x * 4 + c] = uint8_t(std::clamp(std::lround((v[c] - offset) * scale), 0L, 255L));
      out[x * 4 + 3] = uint8_t(std::clamp(std::lround(v[3]), 0L, 255L));
    }
  }
  return {};
}

}  // namespace terralod
