#include "terralod/raster/synthetic_dem_writer.h"

#include <gdal_priv.h>
#include <ogr_spatialref.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <memory>
#include <vector>

#include "gdal_support.h"
#include "terralod/core/parallel.h"
#include "terralod/raster/synthetic_terrain.h"

namespace terralod {
namespace {

constexpr int kTileSide = 256;
// A strip is this many tile rows: enough work per parallel step, a bounded amount of memory
// (65537 columns x 256 rows of float32 is 67 MB).
constexpr int kStripRows = kTileSide;
// Columns generated per task; SyntheticTerrain evaluates in 256-column chunks anyway.
constexpr int kTaskColumns = 4096;

Status checkOptions(const SyntheticDemOptions& o) {
  auto sideOk = [](int64_t side) { return side >= 2 && side <= kMaxSyntheticSide; };
  if (!sideOk(o.columns) || !sideOk(o.rows))
    return makeError(o.output, "raster size " + std::to_string(o.columns) + "x" +
                                   std::to_string(o.rows) + " is outside 2.." +
                                   std::to_string(kMaxSyntheticSide) + " samples per side");
  if (!(o.spacing > 0) || !std::isfinite(o.spacing) || o.spacing > 1e5)
    return makeError(o.output, "spacing must be a positive number of metres up to 100 km");
  const std::string& c = o.compression;
  if (c != "zstd" && c != "deflate" && c != "lzw" && c != "none")
    return makeError(o.output, "unknown compression '" + c + "' (zstd, deflate, lzw, none)");
  return {};
}

std::string gdalCompression(const std::string& name) {
  std::string upper = name;
  std::transform(upper.begin(), upper.end(), upper.begin(), ::toupper);
  return upper;
}

// The temporary file beside the target: hidden, unique per process.
std::string temporaryPathFor(const std::string& output) {
  const std::filesystem::path target(output);
  const std::string name =
      "." + target.filename().string() + ".partial-" + std::to_string(::getpid()) + ".tif";
  return (target.parent_path() / name).string();
}

struct DatasetCloser {
  void operator()(GDALDataset* d) const { GDALClose(GDALDataset::ToHandle(d)); }
};
using DatasetPtr = std::unique_ptr<GDALDataset, DatasetCloser>;

Result<DatasetPtr> createDataset(const SyntheticDemOptions& o, const std::string& path) {
  GDALDriver* driver = GetGDALDriverManager()->GetDriverByName("GTiff");
  if (!driver) return makeError(o.output, "GDAL has no GeoTIFF driver");
  const double bytes = double(o.columns) * double(o.rows) * 4.0;
  CPLStringList createOptions;
  createOptions.SetNameValue("TILED", "YES");
  createOptions.SetNameValue("BLOCKXSIZE", std::to_string(kTileSide).c_str());
  createOptions.SetNameValue("BLOCKYSIZE", std::to_string(kTileSide).c_str());
  createOptions.SetNameValue("COMPRESS", gdalCompression(o.compression).c_str());
  // No floating-point predictor: it would make the file 40 % smaller, but undoing it costs
  // more than the rest of reading, and the build reads every tile twice (docs/benchmarks.md).
  if (o.compression != "none")
    createOptions.SetNameValue("NUM_THREADS", std::to_string(o.threads).c_str());
  if (o.compression == "zstd") createOptions.SetNameValue("ZSTD_LEVEL", "1");
  // Compressed sizes are unknown up front; BigTIFF whenever classic TIFF's 4 GB could be near.
  createOptions.SetNameValue("BIGTIFF", bytes > 2e9 ? "YES" : "NO");
  GDALDataset* ds = driver->Create(path.c_str(), int(o.columns), int(o.rows), 1, GDT_Float32,
                                   createOptions.List());
  if (!ds) return makeError(o.output, "cannot create file: " + gdal::lastErrorMessage());
  DatasetPtr dataset(ds);

  // Pixel-is-area: sample (c, r) is the centre of its cell, and the south-west sample's centre
  // is the world origin.
  const double dx = o.spacing, dy = o.spacing;
  double geoTransform[6] = {-0.5 * dx, dx, 0.0, (double(o.rows) - 0.5) * dy, 0.0, -dy};
  OGRSpatialReference srs;
  srs.SetLocalCS("terralod synthetic terrain (metres, origin at the south-west sample)");
  srs.SetLinearUnits(SRS_UL_METER, 1.0);
  if (dataset->SetGeoTransform(geoTransform) != CE_None || dataset->SetSpatialRef(&srs) != CE_None)
    return makeError(o.output, "cannot write georeferencing: " + gdal::lastErrorMessage());
  GDALRasterBand* band = dataset->GetRasterBand(1);
  band->SetUnitType("m");
  dataset->SetMetadataItem("TERRALOD_SYNTH_SEED", std::to_string(o.seed).c_str());
  dataset->SetMetadataItem("TERRALOD_SYNTH_SPACING", std::to_string(o.spacing).c_str());
  return dataset;
}

Status writeStrips(const SyntheticDemOptions& o, GDALDataset& dataset, unsigned threads,
                   Progress& progress) {
  const SyntheticTerrain terrain(o.seed, o.spacing);
  GDALRasterBand* band = dataset.GetRasterBand(1);
  std::vector<float> strip(size_t(o.columns) * kStripRows);
  const size_t tasks = size_t((o.columns + kTaskColumns - 1) / kTaskColumns);
  progress.begin("synth", uint64_t(o.rows));
  for (int64_t row0 = 0; row0 < o.rows; row0 += kStripRows) {
    const int rows = int(std::min<int64_t>(kStripRows, o.rows - row0));
    std::vector<float> window;
    // Each task fills a block of columns into a window of its own, then copies it into the
    // strip: SyntheticTerrain writes rows of exactly the width it was asked for.
    parallelFor(tasks, threads, [&](size_t task, unsigned) {
      const int64_t column0 = int64_t(task) * kTaskColumns;
      const int columns = int(std::min<int64_t>(kTaskColumns, o.columns - column0));
      std::vector<float> block(size_t(columns) * size_t(rows));
      terrain.fillWindow(column0, row0, columns, rows, block.data());
      for (int r = 0; r < rows; ++r)
        std::copy_n(block.data() + size_t(r) * columns, columns,
                    strip.data() + size_t(r) * size_t(o.columns) + size_t(column0));
    });
    if (band->RasterIO(GF_Write, 0, int(row0), int(o.columns), rows, strip.data(), int(o.columns),
                       rows, GDT_Float32, 0, 0, nullptr) != CE_None)
      return makeError(o.output, "write failed: " + gdal::lastErrorMessage());
    progress.advance(uint64_t(rows));
  }
  progress.end();
  return {};
}

}  // namespace

Status writeSyntheticDem(const SyntheticDemOptions& options, Progress& progress) {
  if (Status ok = checkOptions(options); !ok) return ok;
  gdal::ensureRegistered();
  gdal::QuietErrors quiet;
  SyntheticDemOptions o = options;
  o.threads = options.threads ? options.threads : hardwareThreads();
  const std::string temporary = temporaryPathFor(o.output);
  auto removeTemporary = [&] {
    std::error_code ignored;
    std::filesystem::remove(temporary, ignored);
  };
  {
    auto dataset = createDataset(o, temporary);
    if (!dataset) {
      removeTemporary();
      return dataset.error();
    }
    Status written = writeStrips(o, **dataset, o.threads, progress);
    if (written) {
      // Closing flushes the last tiles and the directory; its failure is a write failure too.
      GDALDataset* raw = dataset->release();
      CPLErrorReset();
      GDALClose(GDALDataset::ToHandle(raw));
      if (CPLGetLastErrorType() >= CE_Failure)
        written = makeError(o.output, "write failed: " + gdal::lastErrorMessage());
    }
    if (!written) {
      dataset->reset();
      removeTemporary();
      return written;
    }
  }
  std::error_code error;
  std::filesystem::rename(temporary, o.output, error);
  if (error) {
    removeTemporary();
    return makeError(o.output, "cannot rename the finished file into place: " + error.message());
  }
  return {};
}

}  // namespace terralod
