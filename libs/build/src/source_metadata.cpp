#include "source_metadata.h"

#include <filesystem>

namespace terralod {

nlohmann::json sourceMetadata(const DemInfo& info) {
  nlohmann::json source = {
      {"file", std::filesystem::path(info.path).filename().string()},
      {"driver", info.driver},
      {"data_type", info.dataType},
      {"columns", info.columns},
      {"rows", info.rows},
      {"spacing", {info.spacingX, info.spacingY}},
      {"spacing_source", info.spacingSource},
      {"crs_wkt", info.earthCrsWkt},
      {"encoding", info.encoding == HeightEncoding::kPlain        ? "none"
                   : info.encoding == HeightEncoding::kTerrainRgb ? "terrain-rgb"
                                                                  : "terrarium"},
  };
  // A raster without a CRS whose bounds were taken as degrees: placed as WGS 84 (exports).
  if (info.crsWkt.empty() && !info.earthCrsWkt.empty()) source["crs_assumed"] = true;
  if (info.hasGeoTransform) source["geotransform"] = info.geoTransform;
  if (info.nodata) source["nodata"] = *info.nodata;
  // Only multi-band sources say which band held the heights: single-band tilesets keep their
  // bytes (and the golden files stay valid).
  if (info.encoding == HeightEncoding::kPlain && info.bandCount > 1) source["band"] = info.band;
  return source;
}

void warnAboutSource(const DemInfo& info, const std::function<void(const std::string&)>& warn) {
  if (info.looksLikeImage)
    warn(info.path +
         ": looks like an image, not heights (one 8-bit band, no georeferencing): its values "
         "0..255 are taken as metres on 1 m cells; for a heightmap give --spacing and "
         "--vertical-scale");
  else if (info.spacingAssumed)
    warn(info.path + ": " + info.spacingSource);
}

}  // namespace terralod
