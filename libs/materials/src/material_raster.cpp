#include "terralod/materials/material_raster.h"

#include <gdal.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <deque>
#include <filesystem>
#include <map>
#include <memory>
#include <set>
#include <vector>

#include "gdal_support.h"
#include "terralod/materials/palette.h"

namespace terralod {
namespace {

constexpr int32_t kDemStripRows = 256;
constexpr uint8_t kUncovered = 255;

using gdal::Dataset;

std::string fileName(const std::string& path) {
  return std::filesystem::path(path).filename().string();
}

bool isGeoreferenced(GDALDatasetH ds) {
  double gt[6];
  return GDALGetGeoTransform(ds, gt) == CE_None || GDALGetGCPCount(ds) > 0;
}

// The material raster warped onto the DEM's pixel grid (north-up, the DEM's bounds and size):
// band 1 the value, band 2 an alpha that is 0 where the raster has no data.
Result<Dataset> warpOntoDem(const std::string& path, GDALDatasetH source, const DemInfo& dem) {
  const auto& g = dem.geoTransform;
  const double xa = g[0], xb = g[0] + double(dem.columns) * g[1];
  const double ya = g[3], yb = g[3] + double(dem.rows) * g[5];
  std::vector<std::string> args = {"-of",
                                   "VRT",
                                   "-te",
                                   gdal::exactNumber(std::min(xa, xb)),
                                   gdal::exactNumber(std::min(ya, yb)),
                                   gdal::exactNumber(std::max(xa, xb)),
                                   gdal::exactNumber(std::max(ya, yb)),
                                   "-ts",
                                   std::to_string(dem.columns),
                                   std::to_string(dem.rows),
                                   "-r",
                                   "near",
                                   "-et",
                                   "0",
                                   "-ot",
                                   "Float64",
                                   "-dstalpha"};
  const char* sourceWkt = GDALGetProjectionRef(source);
  if (!dem.crsWkt.empty() && sourceWkt && *sourceWkt)
    args.insert(args.end(), {"-t_srs", dem.crsWkt});
  Dataset warped = gdal::warp(source, std::move(args));
  if (!warped) {
    const std::string why = gdal::lastErrorMessage();
    return makeError(path, "cannot be reprojected onto the DEM " + fileName(dem.path) +
                               (why.empty() ? "" : ": " + why));
  }
  return warped;
}

// Names and colours the raster itself carries for `value`.
struct OwnLabels {
  std::map<int, std::string> names;
  std::map<int, std::array<uint8_t, 3>> colors;
};

OwnLabels readOwnLabels(GDALRasterBandH band) {
  OwnLabels labels;
  if (GDALColorTableH table = GDALGetRasterColorTable(band)) {
    for (int i = 0; i < std::min(GDALGetColorEntryCount(table), 256); ++i) {
      GDALColorEntry e;
      if (GDALGetColorEntryAsRGB(table, i, &e))
        labels.colors[i] = {uint8_t(std::clamp<short>(e.c1, 0, 255)),
                            uint8_t(std::clamp<short>(e.c2, 0, 255)),
                            uint8_t(std::clamp<short>(e.c3, 0, 255))};
    }
  }
  if (GDALRasterAttributeTableH rat = GDALGetDefaultRAT(band)) {
    int valueCol = -1, nameCol = -1, rgb[3] = {-1, -1, -1};
    for (int c = 0; c < GDALRATGetColumnCount(rat); ++c) {
      switch (GDALRATGetUsageOfCol(rat, c)) {
        case GFU_MinMax:
        case GFU_Min:
          if (valueCol < 0) valueCol = c;
          break;
        case GFU_Name:
          if (nameCol < 0) nameCol = c;
          break;
        case GFU_Red:
          rgb[0] = c;
          break;
        case GFU_Green:
          rgb[1] = c;
          break;
        case GFU_Blue:
          rgb[2] = c;
          break;
        default:
          break;
      }
    }
    for (int r = 0; r < GDALRATGetRowCount(rat); ++r) {
      const int value = valueCol >= 0 ? GDALRATGetValueAsInt(rat, r, valueCol) : r;
      if (value < 0 || value > 255) continue;
      if (nameCol >= 0) {
        const char* name = GDALRATGetValueAsString(rat, r, nameCol);
        if (name && *name) labels.names[value] = name;
      }
      if (rgb[0] >= 0 && rgb[1] >= 0 && rgb[2] >= 0 && !labels.colors.count(value)) {
        std::array<uint8_t, 3> color;
        for (int k = 0; k < 3; ++k)
          color[size_t(k)] = uint8_t(std::clamp(GDALRATGetValueAsInt(rat, r, rgb[k]), 0, 255));
        labels.colors[value] = color;
      }
    }
  }
  if (char** names = GDALGetRasterCategoryNames(band)) {
    for (int i = 0; names[i] && i < 256; ++i)
      if (*names[i]) labels.names[i] = names[i];
  }
  for (int value = 0; value < 256; ++value) {
    if (labels.names.count(value)) continue;
    const std::string key = "CLASS_NAME_" + std::to_string(value);
    if (const char* name = GDALGetMetadataItem(band, key.c_str(), nullptr); name && *name)
      labels.names[value] = name;
  }
  return labels;
}

// Gives every uncovered point the class of the nearest covered one, breadth first from all
// covered points at once (4-connected steps, seeds in scan order).
void fillUncovered(MaterialMap& map) {
  const int32_t w = map.columns, h = map.rows;
  std::deque<uint32_t> queue;
  auto uncovered = [&](int32_t x, int32_t y) {
    return map.classes[size_t(y) * size_t(w) + size_t(x)] == kUncovered;
  };
  for (int32_t y = 0; y < h; ++y)
    for (int32_t x = 0; x < w; ++x) {
      if (uncovered(x, y)) continue;
      if ((x > 0 && uncovered(x - 1, y)) || (x + 1 < w && uncovered(x + 1, y)) ||
          (y > 0 && uncovered(x, y - 1)) || (y + 1 < h && uncovered(x, y + 1)))
        queue.push_back(uint32_t(y) * uint32_t(w) + uint32_t(x));
    }
  while (!queue.empty()) {
    const uint32_t i = queue.front();
    queue.pop_front();
    const int32_t x = int32_t(i % uint32_t(w)), y = int32_t(i / uint32_t(w));
    const uint8_t c = map.classes[i];
    const int32_t nx[4] = {x - 1, x + 1, x, x}, ny[4] = {y, y, y - 1, y + 1};
    for (int k = 0; k < 4; ++k) {
      if (nx[k] < 0 || nx[k] >= w || ny[k] < 0 || ny[k] >= h || !uncovered(nx[k], ny[k])) continue;
      const uint32_t j = uint32_t(ny[k]) * uint32_t(w) + uint32_t(nx[k]);
      map.classes[j] = c;
      queue.push_back(j);
    }
  }
}

}  // namespace

Result<MaterialMap> readMaterialRaster(const std::string& path, const DemInfo& dem,
                                       const MaterialRasterOptions& options) {
  gdal::ensureRegistered();
  gdal::QuietErrors quiet;

  std::vector<Material> palette;
  if (!options.palettePath.empty()) {
    auto read = readPalette(options.palettePath);
    if (!read) return read.error();
    palette = std::move(read).value();
  }

  std::error_code ec;
  if (path.rfind("/vsi", 0) != 0 && !std::filesystem::exists(path, ec))
    return makeError(path, "no such file");
  Dataset source(
      GDALOpenEx(path.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY, nullptr, nullptr, nullptr));
  if (!source || GDALGetRasterCount(source.get()) < 1)
    return makeError(path, "not a raster GDAL can read");
  GDALRasterBandH sourceBand = GDALGetRasterBand(source.get(), 1);

  // Where to read values and validity from, and how raster rows map to grid rows.
  Dataset warped;
  GDALRasterBandH valueBand = nullptr, validBand = nullptr;
  const bool sourceGeo = isGeoreferenced(source.get());
  if (sourceGeo && dem.hasGeoTransform) {
    auto w = warpOntoDem(path, source.get(), dem);
    if (!w) return w.error();
    warped = std::move(w).value();
    valueBand = GDALGetRasterBand(warped.get(), 1);
    validBand = GDALGetRasterBand(warped.get(), 2);
  } else if (sourceGeo) {
    return makeError(path, "is georeferenced but the DEM " + fileName(dem.path) +
                               " has no georeferencing, so it cannot be placed on the DEM");
  } else if (dem.hasGeoTransform) {
    return makeError(
        path, "has no georeferencing, so it cannot be placed on the DEM " + fileName(dem.path));
  } else if (GDALGetRasterXSize(source.get()) != dem.columns ||
             GDALGetRasterYSize(source.get()) != dem.rows) {
    return makeError(path, "has no georeferencing and its size " +
                               std::to_string(GDALGetRasterXSize(source.get())) + "x" +
                               std::to_string(GDALGetRasterYSize(source.get())) +
                               " differs from the DEM's");
  } else {
    valueBand = sourceBand;
    validBand = GDALGetMaskBand(sourceBand);
  }

  MaterialMap map;
  map.columns = dem.columns;
  map.rows = dem.rows;
  map.classes.assign(size_t(dem.columns) * size_t(dem.rows), 0);
  std::vector<bool> isCovered(map.classes.size(), false);  // 255 is a class value too
  std::array<bool, 256> used{};
  std::set<double> outOfRange;
  int distinct = 0;
  uint64_t covered = 0;
  const std::string continuous = "looks like continuous data, not classes";
  std::vector<double> values(size_t(dem.columns) * kDemStripRows);
  std::vector<uint8_t> valid(values.size());
  for (int32_t row0 = 0; row0 < dem.rows; row0 += kDemStripRows) {
    const int32_t h = std::min(kDemStripRows, dem.rows - row0);
    if (GDALRasterIO(valueBand, GF_Read, 0, row0, dem.columns, h, values.data(), dem.columns, h,
                     GDT_Float64, 0, 0) != CE_None ||
        GDALRasterIO(validBand, GF_Read, 0, row0, dem.columns, h, valid.data(), dem.columns, h,
                     GDT_Byte, 0, 0) != CE_None) {
      const std::string why = gdal::lastErrorMessage();
      return makeError(path, "read failed" + (why.empty() ? "" : ": " + why));
    }
    for (int32_t r = 0; r < h; ++r) {
      const size_t rowStart = size_t(dem.rows - 1 - (row0 + r)) * size_t(dem.columns);
      uint8_t* out = map.classes.data() + rowStart;
      for (int32_t x = 0; x < dem.columns; ++x) {
        const size_t i = size_t(r) * size_t(dem.columns) + size_t(x);
        if (!valid[i]) continue;
        const double v = values[i];
        if (!std::isfinite(v) || v != std::floor(v)) {
          return makeError(path, "has non-integer values (e.g. " + gdal::exactNumber(v) +
                                     ") over the DEM: " + continuous);
        }
        ++covered;
        isCovered[rowStart + size_t(x)] = true;
        if (v >= 0 && v <= 255) {
          const auto value = uint8_t(v);
          if (!used[value]) used[value] = true, ++distinct;
          out[x] = value;
        } else if (outOfRange.insert(v).second) {
          ++distinct;
        }
        if (distinct > kMaxDistinctValuesForClasses)
          return makeError(path, "has more than " + std::to_string(kMaxDistinctValuesForClasses) +
                                     " distinct values over the DEM: " + continuous);
      }
    }
  }
  if (covered == 0)
    return makeError(path, "does not overlap the DEM " + fileName(dem.path) +
                               " (no class at any of its points)");
  if (!outOfRange.empty())
    return makeError(path, "has class value " + gdal::exactNumber(*outOfRange.begin()) +
                               "; class values must be whole numbers 0..255");
  if (distinct > kMaxMaterials)
    return makeError(path, "has " + std::to_string(distinct) + " classes over the DEM; at most " +
                               std::to_string(kMaxMaterials) + " are supported");

  const OwnLabels own = palette.empty() ? readOwnLabels(sourceBand) : OwnLabels{};
  std::array<uint8_t, 256> indexOf{};
  for (int value = 0; value < 256; ++value) {
    if (!used[size_t(value)]) continue;
    Material m;
    m.id = uint8_t(value);
    if (!palette.empty()) {
      auto it = std::find_if(palette.begin(), palette.end(),
                             [&](const Material& p) { return p.id == value; });
      if (it == palette.end())
        return makeError(path, "has class value " + std::to_string(value) + ", which the palette " +
                                   options.palettePath + " lacks");
      m = *it;
    } else {
      auto name = own.names.find(value);
      m.name = name != own.names.end() ? name->second : "class " + std::to_string(value);
      auto color = own.colors.find(value);
      m.color = color != own.colors.end() ? color->second : distinctColor(map.materials.size());
    }
    indexOf[size_t(value)] = uint8_t(map.materials.size());
    map.materials.push_back(std::move(m));
  }
  for (size_t i = 0; i < map.classes.size(); ++i)
    map.classes[i] = isCovered[i] ? indexOf[map.classes[i]] : kUncovered;
  if (covered < map.classes.size()) fillUncovered(map);
  return map;
}

Result<MaterialMap> readMaterialRaster(const std::string& path, const SourceGrid& grid,
                                       const std::string& gridName,
                                       const MaterialRasterOptions& options) {
  DemInfo dem;
  dem.path = gridName;
  dem.columns = grid.columns;
  dem.rows = grid.rows;
  dem.spacingX = grid.spacingX;
  dem.spacingY = grid.spacingY;
  dem.geoTransform = grid.geoTransform;
  dem.hasGeoTransform = grid.hasGeoTransform;
  dem.crsWkt = grid.crsWkt;
  return readMaterialRaster(path, dem, options);
}

}  // namespace terralod
