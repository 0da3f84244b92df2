#include "terralod/raster/dem_reader.h"

#include <gdal_priv.h>
#include <ogr_spatialref.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <limits>
#include <memory>
#include <numbers>
#include <vector>

#include "gdal_support.h"

namespace terralod {
namespace {

constexpr int64_t kMaxSide = int64_t{1} << 20;
constexpr int64_t kMaxSamples = int64_t{1} << 34;

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

// A height in metres as a stored sample: a void (NaN) unless finite within float's range, so a
// value such as 1e300 counts as the infinity it would otherwise become after the void checks.
float storedHeight(double metres) {
  return std::fabs(metres) <= double(std::numeric_limits<float>::max()) ? float(metres)
                                                                        : std::nanf("");
}

bool looksLikeGdalSpecialPath(const std::string& path) {
  return path.rfind("/vsi", 0) == 0 || path.find(':') != std::string::npos;
}

// netCDF and HDF files often hold several variables; pick the elevation-like one.
std::string chooseSubdataset(GDALDataset& dataset) {
  char** list = dataset.GetMetadata("SUBDATASETS");
  std::vector<std::string> names;
  for (char** item = list; item && *item; ++item) {
    std::string entry = *item;
    const auto eq = entry.find('=');
    if (eq == std::string::npos) continue;
    const std::string key = entry.substr(0, eq);
    if (key.size() > 5 && key.compare(key.size() - 5, 5, "_NAME") == 0)
      names.push_back(entry.substr(eq + 1));
  }
  if (names.empty()) return {};
  static const char* kPreferred[] = {"elevation", "elev", "height", "altitude", "topo",
                                     "dem",       "hgt",  "z",      "band1"};
  for (const char* wanted : kPreferred) {
    for (const auto& name : names) {
      const auto colon = name.rfind(':');
      std::string variable = lower(colon == std::string::npos ? name : name.substr(colon + 1));
      variable.erase(std::remove(variable.begin(), variable.end(), '"'), variable.end());
      if (variable == wanted) return name;
    }
  }
  return names.front();
}

// Metres per unit of a band's vertical unit string; nullopt when unrecognised.
std::optional<double> verticalUnitFactor(std::string unit) {
  unit = lower(unit);
  if (unit.empty() || unit == "m" || unit == "metre" || unit == "meter" || unit == "metres" ||
      unit == "meters")
    return 1.0;
  if (unit == "ft" || unit == "foot" || unit == "feet" || unit == "international foot")
    return 0.3048;
  if (unit == "us-ft" || unit == "ftus" || unit == "us survey foot" || unit == "us_survey_foot")
    return 1200.0 / 3937.0;
  if (unit == "km" || unit == "kilometre" || unit == "kilometer") return 1000.0;
  return std::nullopt;
}

// `srs` as WKT ("" if GDAL cannot write it).
std::string wktOf(const OGRSpatialReference& srs) {
  char* wkt = nullptr;
  std::string out;
  if (srs.exportToWkt(&wkt) == OGRERR_NONE && wkt) out = wkt;
  CPLFree(wkt);
  return out;
}

// A raster without a CRS is taken as WGS 84 degrees when its bounds lie inside the
// longitude/latitude range and its cells are small.
bool boundsLookLikeDegrees(const DemInfo& info) {
  const auto& gt = info.geoTransform;
  const double west = gt[0], north = gt[3];
  const double east = west + gt[1] * info.columns, south = north + gt[5] * info.rows;
  const bool inLonLat = std::min(west, east) >= -180.0 && std::max(west, east) <= 360.0 &&
                        std::min(south, north) >= -90.0 && std::max(south, north) <= 90.0;
  return inLonLat && std::fabs(gt[1]) < 0.1 && std::fabs(gt[5]) < 0.1;
}

// Metres per cell from an axis-aligned geotransform and the CRS (or a documented guess without
// one).
Status deriveSpacing(GDALDataset& dataset, DemInfo& info) {
  const auto& gt = info.geoTransform;
  if (gt[2] != 0.0 || gt[4] != 0.0)
    return makeError(info.path, "raster is rotated or sheared; warp it north-up first (gdalwarp)");
  const double cellX = std::fabs(gt[1]), cellY = std::fabs(gt[5]);
  if (!(cellX > 0) || !(cellY > 0) || !std::isfinite(cellX) || !std::isfinite(cellY))
    return makeError(info.path, "georeferencing has a zero or invalid cell size");

  const OGRSpatialReference* srs = dataset.GetSpatialRef();
  bool geographic = false;
  double angularUnit = std::numbers::pi / 180.0;  // radians per unit
  double semiMajor = 6378137.0, inverseFlattening = 298.257223563;
  if (srs && (srs->IsProjected() || srs->IsLocal())) {
    const double metresPerUnit = srs->GetLinearUnits();
    info.spacingX = cellX * metresPerUnit;
    info.spacingY = cellY * metresPerUnit;
    info.spacingSource = srs->IsProjected() ? "projected CRS" : "local CRS";
    if (metresPerUnit != 1.0) info.spacingSource += " (units converted to metres)";
    return {};
  }
  if (srs && srs->IsGeographic()) {
    geographic = true;
    angularUnit = srs->GetAngularUnits();
    OGRErr err = OGRERR_NONE;
    semiMajor = srs->GetSemiMajor(&err);
    inverseFlattening = srs->GetInvFlattening(&err);
  } else if (!srs || srs->IsEmpty()) {
    // No CRS (e.g. an ESRI ASCII grid without .prj): small cells inside the lon/lat range are
    // taken as WGS 84 degrees, anything else as metres.
    if (boundsLookLikeDegrees(info)) {
      geographic = true;
      OGRSpatialReference wgs84;
      if (wgs84.SetWellKnownGeogCS("WGS84") == OGRERR_NONE) info.earthCrsWkt = wktOf(wgs84);
    } else {
      info.spacingX = cellX;
      info.spacingY = cellY;
      info.spacingSource = "no CRS: cell size taken as metres";
      return {};
    }
  } else {
    info.spacingX = cellX;
    info.spacingY = cellY;
    info.spacingSource = "unrecognised CRS: cell size taken as metres";
    return {};
  }
  if (geographic) {
    // Local radii of curvature of the ellipsoid at the raster's centre latitude.
    const double latitude = (gt[3] + gt[5] * info.rows * 0.5) * angularUnit;
    const double f = inverseFlattening > 0 ? 1.0 / inverseFlattening : 0.0;
    const double e2 = f * (2.0 - f);
    const double s = std::sin(latitude);
    const double w = std::sqrt(1.0 - e2 * s * s);
    const double primeVertical = semiMajor / w;
    const double meridional = semiMajor * (1.0 - e2) / (w * w * w);
    info.spacingX = cellX * angularUnit * primeVertical * std::cos(latitude);
    info.spacingY = cellY * angularUnit * meridional;
    char text[160];
    std::snprintf(text, sizeof text, "geographic degrees converted at latitude %.4f%s",
                  latitude * 180.0 / std::numbers::pi,
                  srs && !srs->IsEmpty() ? "" : " (no CRS: WGS 84 degrees assumed)");
    info.spacingSource = text;
    if (!(info.spacingX > 0) || !(info.spacingY > 0))
      return makeError(info.path, "geographic raster reaches a pole; cannot derive spacing");
  }
  return {};
}

std::string sizeText(uint64_t bytes) {
  return bytes >= (uint64_t{1} << 20) ? std::to_string(bytes >> 20) + " MB"
                                      : std::to_string(bytes >> 10) + " KB";
}

// GDAL decodes a raster block by block, each into one buffer; a pixel-interleaved block holds
// every band. A few hundred bytes of TIFF header can declare one block of gigabytes (found by
// the raster fuzzer: a 241-byte file, one LZW strip of 63148x3596 pixels of 12 bands, made
// GDAL allocate 5.4 GB), so blocks over DemOpenOptions::maxBlockBytes are refused before any
// is read.
Status checkBlockSize(GDALDataset& dataset, GDALRasterBand& band, const std::string& path,
                      uint64_t maxBlockBytes) {
  int blockX = 0, blockY = 0;
  band.GetBlockSize(&blockX, &blockY);
  const char* interleave = dataset.GetMetadataItem("INTERLEAVE", "IMAGE_STRUCTURE");
  const bool pixelInterleaved = interleave && std::string(interleave) == "PIXEL";
  const uint64_t bands = pixelInterleaved ? uint64_t(dataset.GetRasterCount()) : 1;
  const uint64_t bytes = uint64_t(std::max(blockX, 1)) * uint64_t(std::max(blockY, 1)) * bands *
                         uint64_t(GDALGetDataTypeSizeBytes(band.GetRasterDataType()));
  if (bytes <= maxBlockBytes) return {};
  return makeError(
      path, "its blocks of " + std::to_string(blockX) + "x" + std::to_string(blockY) + " samples" +
                (bands > 1 ? " x " + std::to_string(bands) + " bands" : "") + " need " +
                sizeText(bytes) + " each, more than " + sizeText(maxBlockBytes) +
                "; rewrite it tiled (gdal_translate -co TILED=YES)");
}

}  // namespace

struct DemReader::Impl {
  GDALDatasetUniquePtr dataset;
  std::string openedName;  // what was passed to GDALOpen (may be a subdataset)
  int bandCount = 1;
  int band = 1;  // the band read as heights (plain encoding)
  GDALDataType bandType = GDT_Float64;
};

void setGdalCacheBytes(uint64_t bytes) {
  gdal::ensureRegistered();
  GDALSetCacheMax64(static_cast<GIntBig>(bytes));
}

std::optional<HeightEncoding> parseHeightEncoding(const std::string& text) {
  const std::string t = lower(text);
  if (t == "none" || t == "plain") return HeightEncoding::kPlain;
  if (t == "terrain-rgb" || t == "mapbox") return HeightEncoding::kTerrainRgb;
  if (t == "terrarium" || t == "mapzen") return HeightEncoding::kTerrarium;
  return std::nullopt;
}

DemReader::DemReader(std::unique_ptr<Impl> impl, DemInfo info, DemOpenOptions options)
    : mImpl(std::move(impl)), mInfo(std::move(info)), mOptions(std::move(options)) {}

DemReader::~DemReader() = default;

Result<std::unique_ptr<DemReader>> DemReader::open(const std::string& path,
                                                   const DemOpenOptions& options) {
  gdal::ensureRegistered();
  gdal::QuietErrors quiet;
  if (!looksLikeGdalSpecialPath(path)) {
    std::error_code ec;
    if (!std::filesystem::exists(path, ec)) return makeError(path, "no such file");
    if (std::filesystem::is_directory(path, ec))
      return makeError(path, "is a directory, not a raster");
    if (std::filesystem::file_size(path, ec) == 0) return makeError(path, "file is empty");
  }
  auto impl = std::make_unique<Impl>();
  impl->openedName = path;
  impl->dataset.reset(GDALDataset::Open(path.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY));
  if (!impl->dataset) {
    const std::string why = gdal::lastErrorMessage();
    return makeError(path, "not a raster GDAL can read" + (why.empty() ? "" : " (" + why + ")"));
  }
  if (impl->dataset->GetRasterCount() == 0) {
    const std::string sub = chooseSubdataset(*impl->dataset);
    if (sub.empty()) return makeError(path, "contains no raster bands");
    impl->dataset.reset(GDALDataset::Open(sub.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY));
    if (!impl->dataset || impl->dataset->GetRasterCount() == 0)
      return makeError(path, "cannot open its raster variable " + sub);
    impl->openedName = sub;
  }
  GDALDataset& ds = *impl->dataset;

  DemInfo info;
  info.path = path;
  info.encoding = options.encoding;
  info.driver = ds.GetDriver() ? ds.GetDriver()->GetDescription() : "";
  info.columns = ds.GetRasterXSize();
  info.rows = ds.GetRasterYSize();
  impl->bandCount = ds.GetRasterCount();
  if (info.columns < 2 || info.rows < 2)
    return makeError(path, "raster is " + std::to_string(info.columns) + "x" +
                               std::to_string(info.rows) + " samples; terralod needs at least 2x2");
  if (info.columns > kMaxSide || info.rows > kMaxSide ||
      int64_t(info.columns) * info.rows > kMaxSamples)
    return makeError(path,
                     "raster is " + std::to_string(info.columns) + "x" + std::to_string(info.rows) +
                         " samples, more than terralod supports (1048576 per side, 2^34 in all)");

  info.bandCount = impl->bandCount;
  const bool plain = options.encoding == HeightEncoding::kPlain;
  if (plain && options.band != 0 && (options.band < 1 || options.band > impl->bandCount))
    return makeError(path, "has " + std::to_string(impl->bandCount) +
                               " band(s); --band must be 1 to " + std::to_string(impl->bandCount) +
                               " (got " + std::to_string(options.band) + ")");
  impl->band = plain && options.band != 0 ? options.band : 1;
  info.band = impl->band;
  GDALRasterBand* band = ds.GetRasterBand(impl->band);
  impl->bandType = band->GetRasterDataType();
  info.dataType = GDALGetDataTypeName(impl->bandType);
  if (Status s = checkBlockSize(ds, *band, path, options.maxBlockBytes); !s) return s.error();
  // Several 8-bit bands are a photo or an RGB-encoded web tile: band 1 alone would be its red
  // channel, read as 0..255 m (or, for terrain-RGB, a flat slab of its high byte).
  if (plain && options.band == 0 && impl->bandCount > 1 && impl->bandType == GDT_Byte)
    return makeError(path, "has " + std::to_string(impl->bandCount) +
                               " bands of 8-bit values, like a picture, not heights: give "
                               "--encoding terrain-rgb|terrarium for RGB-encoded heights, or "
                               "--band N to take one band as heights");
  if (!plain) {
    if (impl->bandCount < 3 || impl->bandType != GDT_Byte)
      return makeError(path, "RGB-encoded heights need 3 byte bands; this raster has " +
                                 std::to_string(impl->bandCount) + " band(s) of " + info.dataType);
  } else {
    int hasNodata = 0;
    const double nodata = band->GetNoDataValue(&hasNodata);
    if (hasNodata) info.nodata = nodata;
    int hasScale = 0, hasOffset = 0;
    const double scale = band->GetScale(&hasScale);
    const double offset = band->GetOffset(&hasOffset);
    const auto unitFactor = verticalUnitFactor(band->GetUnitType());
    if (!unitFactor)
      return makeError(path, std::string("unknown vertical unit '") + band->GetUnitType() +
                                 "'; convert heights to metres first");
    info.heightScale = (hasScale ? scale : 1.0) * *unitFactor;
    info.heightOffset = (hasOffset ? offset : 0.0) * *unitFactor;
  }
  info.heightScale *= options.verticalScale;
  info.heightOffset *= options.verticalScale;

  if (const OGRSpatialReference* srs = ds.GetSpatialRef()) info.crsWkt = wktOf(*srs);
  info.hasGeoTransform = ds.GetGeoTransform(info.geoTransform.data()) == CE_None;
  if (info.hasGeoTransform && info.geoTransform[1] < 0.0)
    return makeError(path, "raster columns run east to west; warp it first (gdalwarp)");
  // Rows may run either way; readWindow turns both into grid order (south row first).
  info.southUp = info.hasGeoTransform && info.geoTransform[5] > 0.0;
  if (options.spacing) {
    info.spacingX = (*options.spacing)[0];
    info.spacingY = (*options.spacing)[1];
    info.spacingSource = "--spacing";
  } else if (info.hasGeoTransform) {
    if (Status s = deriveSpacing(ds, info); !s) return s.error();
  } else {
    info.spacingX = info.spacingY = 1.0;
    info.spacingAssumed = true;
    info.spacingSource = "no georeferencing: 1 m assumed (pass --spacing)";
    info.looksLikeImage =
        plain && impl->bandCount == 1 && impl->bandType == GDT_Byte && info.crsWkt.empty();
  }
  if (!(info.spacingX > 0) || !(info.spacingY > 0) || !std::isfinite(info.spacingX) ||
      !std::isfinite(info.spacingY))
    return makeError(path, "horizontal spacing must be positive and finite");
  if (info.earthCrsWkt.empty()) info.earthCrsWkt = info.crsWkt;

  return std::unique_ptr<DemReader>(new DemReader(std::move(impl), std::move(info), options));
}

Result<std::unique_ptr<DemReader>> DemReader::reopen() const {
  auto again = open(mImpl->openedName, mOptions);
  if (again) (*again)->mInfo.path = mInfo.path;
  return again;
}

std::vector<double> DemReader::gridRowLatitudes() const {
  gdal::QuietErrors quiet;
  const DemInfo& info = mInfo;
  if (!info.hasGeoTransform) return {};
  const auto& gt = info.geoTransform;
  // Where raster row r's centre lies along the geotransform's y axis, for grid row gy.
  const int32_t rows = info.rows;
  auto rasterY = [&](int32_t gy) {
    const int32_t r = info.southUp ? gy : rows - 1 - gy;
    return gt[3] + (r + 0.5) * gt[5];
  };
  const double centreX = gt[0] + 0.5 * info.columns * gt[1];
  std::vector<double> latitudes(size_t(rows), 0.0);
  const OGRSpatialReference* srs = mImpl->dataset->GetSpatialRef();
  if (!srs || srs->IsEmpty()) {
    if (!boundsLookLikeDegrees(info)) return {};
    for (int32_t gy = 0; gy < rows; ++gy) latitudes[size_t(gy)] = rasterY(gy);
  } else if (srs->IsGeographic()) {
    const double degreesPerUnit = srs->GetAngularUnits() * 180.0 / std::numbers::pi;
    for (int32_t gy = 0; gy < rows; ++gy) latitudes[size_t(gy)] = rasterY(gy) * degreesPerUnit;
  } else if (srs->IsProjected()) {
    // Through PROJ to the CRS's own geographic CRS, at the centre column of every row.
    OGRSpatialReference source(*srs);
    source.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
    std::unique_ptr<OGRSpatialReference> geographic(source.CloneGeogCS());
    if (!geographic) return {};
    geographic->SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
    std::unique_ptr<OGRCoordinateTransformation> toGeographic(
        OGRCreateCoordinateTransformation(&source, geographic.get()));
    if (!toGeographic) return {};
    std::vector<double> x(size_t(rows), centreX), y(size_t(rows), 0.0);
    for (int32_t gy = 0; gy < rows; ++gy) y[size_t(gy)] = rasterY(gy);
    std::vector<int> ok(size_t(rows), 0);
    if (!toGeographic->Transform(rows, x.data(), y.data(), nullptr, ok.data())) return {};
    const double degreesPerUnit = geographic->GetAngularUnits() * 180.0 / std::numbers::pi;
    for (int32_t gy = 0; gy < rows; ++gy) {
      if (!ok[size_t(gy)] || !std::isfinite(y[size_t(gy)])) return {};
      latitudes[size_t(gy)] = y[size_t(gy)] * degreesPerUnit;
    }
  } else {
    return {};  // a local (engineering) CRS: not placed on Earth
  }
  for (double& latitude : latitudes) latitude = std::clamp(latitude, -90.0, 90.0);
  return latitudes;
}

Result<std::array<double, 2>> DemReader::approximateHeightRange() const {
  gdal::QuietErrors quiet;
  if (mInfo.encoding != HeightEncoding::kPlain) return Error{"no approximate range for RGB tiles"};
  double minMax[2] = {0, 0};
  if (GDALComputeRasterMinMax(mImpl->dataset->GetRasterBand(mImpl->band), TRUE, minMax) != CE_None)
    return makeError(mInfo.path,
                     "cannot estimate the height range (" + gdal::lastErrorMessage() + ")");
  std::array<double, 2> range = {minMax[0] * mInfo.heightScale + mInfo.heightOffset,
                                 minMax[1] * mInfo.heightScale + mInfo.heightOffset};
  if (range[0] > range[1]) std::swap(range[0], range[1]);
  if (!std::isfinite(range[0]) || !std::isfinite(range[1]))
    return makeError(mInfo.path, "height range is not finite");
  return range;
}

Status DemReader::readWindow(int32_t x0, int32_t y0, int32_t w, int32_t h, float* out) const {
  gdal::QuietErrors quiet;
  const int32_t cols = mInfo.columns, rows = mInfo.rows;
  // Clamped source range in grid coordinates.
  const int32_t gx0 = std::clamp(x0, 0, cols - 1), gx1 = std::clamp(x0 + w - 1, 0, cols - 1);
  const int32_t gy0 = std::clamp(y0, 0, rows - 1), gy1 = std::clamp(y0 + h - 1, 0, rows - 1);
  const int32_t readCols = gx1 - gx0 + 1;
  const bool rgb = mInfo.encoding != HeightEncoding::kPlain;
  // 32-bit integers and doubles do not fit a float exactly; everything else is read as float.
  const bool wide = mImpl->bandType == GDT_Float64 || mImpl->bandType == GDT_Int32 ||
                    mImpl->bandType == GDT_UInt32;
  const bool nativeFloat = mImpl->bandType == GDT_Float32;
  const bool hasNodata = mInfo.nodata.has_value();
  const double nodata = hasNodata ? *mInfo.nodata : 0.0;
  const float nodataF = static_cast<float>(nodata);
  const bool identity = mInfo.heightScale == 1.0 && mInfo.heightOffset == 0.0;

  // Strips of whole raster blocks, so each block is decoded once.
  GDALRasterBand* band = mImpl->dataset->GetRasterBand(rgb ? 1 : mImpl->band);
  int blockX = 0, blockY = 0;
  band->GetBlockSize(&blockX, &blockY);
  // Block heights come from the file: clamp before rounding up to whole multiples of 64.
  const int64_t blockRows = std::clamp<int64_t>(blockY, 1, rows);
  const int32_t stripRows = int32_t(std::max<int64_t>(64, (blockRows + 63) / 64 * 64));
  // A strip never holds more rows than the window has (a raster of one tall block must not
  // cost a buffer of its whole height).
  const size_t bufferRows = size_t(std::min(stripRows, gy1 - gy0 + 1));
  std::vector<float> strip(rgb || wide ? 0 : size_t(readCols) * bufferRows);
  std::vector<double> wideStrip(wide ? size_t(readCols) * bufferRows : 0);
  std::vector<uint8_t> rgbStrip(rgb ? size_t(readCols) * bufferRows * 3 : 0);
  std::vector<float> rowValues(readCols);

  // Grid rows run south to north; raster rows usually north to south.
  auto flip = [&](int32_t row) { return mInfo.southUp ? row : rows - 1 - row; };
  // Strips aligned to raster rows, walking the window in raster order.
  const int32_t rasterFirst = std::min(flip(gy0), flip(gy1));
  const int32_t rasterLast = std::max(flip(gy0), flip(gy1));
  for (int32_t r0 = rasterFirst; r0 <= rasterLast;) {
    const int32_t alignedEnd = (r0 / stripRows + 1) * stripRows;
    const int32_t n = std::min(alignedEnd, rasterLast + 1) - r0;
    CPLErr err;
    if (rgb) {
      int bands[3] = {1, 2, 3};
      err = mImpl->dataset->RasterIO(GF_Read, gx0, r0, readCols, n, rgbStrip.data(), readCols, n,
                                     GDT_Byte, 3, bands, 3, 3 * readCols, 1, nullptr);
    } else if (wide) {
      err = band->RasterIO(GF_Read, gx0, r0, readCols, n, wideStrip.data(), readCols, n,
                           GDT_Float64, 0, 0, nullptr);
    } else {
      err = band->RasterIO(GF_Read, gx0, r0, readCols, n, strip.data(), readCols, n, GDT_Float32, 0,
                           0, nullptr);
    }
    if (err != CE_None) {
      const std::string why = gdal::lastErrorMessage();
      return makeError(mInfo.path, "cannot read raster rows " + std::to_string(r0) + "-" +
                                       std::to_string(r0 + n - 1) +
                                       (why.empty() ? "" : " (" + why + ")"));
    }
    for (int32_t i = 0; i < n; ++i) {
      const size_t base = size_t(i) * readCols;
      if (rgb) {
        for (int32_t c = 0; c < readCols; ++c) {
          const uint8_t* p = &rgbStrip[(base + c) * 3];
          const double value = mInfo.encoding == HeightEncoding::kTerrainRgb
                                   ? (p[0] * 65536.0 + p[1] * 256.0 + p[2]) * 0.1 - 10000.0
                                   : p[0] * 256.0 + p[1] + p[2] / 256.0 - 32768.0;
          rowValues[c] = storedHeight(value * mOptions.verticalScale);
        }
      } else if (wide) {
        for (int32_t c = 0; c < readCols; ++c) {
          const double raw = wideStrip[base + c];
          const bool isVoid = !std::isfinite(raw) || (hasNodata && raw == nodata);
          rowValues[c] =
              isVoid ? std::nanf("") : storedHeight(raw * mInfo.heightScale + mInfo.heightOffset);
        }
      } else {
        const float* src = strip.data() + base;
        for (int32_t c = 0; c < readCols; ++c) {
          const float raw = src[c];
          // Compare nodata in the band's own precision (a float nodata tag is not a double).
          const bool isVoid = !std::isfinite(raw) ||
                              (hasNodata && (nativeFloat ? raw == nodataF : double(raw) == nodata));
          rowValues[c] = isVoid     ? std::nanf("")
                         : identity ? raw
                                    : storedHeight(raw * mInfo.heightScale + mInfo.heightOffset);
        }
      }
      // Emit every output row that maps (after clamping) to this grid row.
      const int32_t gridRow = flip(r0 + i);
      const int32_t oyLo = std::max(0, gridRow == 0 ? 0 : gridRow - y0);
      const int32_t oyHi = std::min(h - 1, gridRow == rows - 1 ? h - 1 : gridRow - y0);
      for (int32_t oy = oyLo; oy <= oyHi; ++oy) {
        float* dst = out + size_t(oy) * w;
        const int32_t insideLo = std::clamp(-x0, 0, w), insideHi = std::clamp(cols - x0, 0, w);
        for (int32_t ox = 0; ox < insideLo; ++ox) dst[ox] = rowValues[0];
        std::copy(rowValues.begin() + (x0 + insideLo - gx0),
                  rowValues.begin() + (x0 + insideHi - gx0), dst + insideLo);
        for (int32_t ox = std::max(insideLo, insideHi); ox < w; ++ox)
          dst[ox] = rowValues[readCols - 1];
      }
    }
    r0 += n;
  }
  return {};
}

}  // namespace terralod
