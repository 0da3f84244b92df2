#include "terralod/build/builder.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <limits>
#include <mutex>
#include <nlohmann/json.hpp>

#include "terralod/build/activation_pass.h"
#include "terralod/build/chunk_encoder.h"
#include "terralod/build/chunk_mesher.h"
#include "terralod/build/error_budget.h"
#include "terralod/build/height_source.h"
#include "terralod/build/tree_layout.h"
#include "terralod/core/parallel.h"
#include "terralod/format/tileset_writer.h"
#include "terralod/raster/heightfield.h"
#include "terralod/raster/void_fill.h"

namespace terralod {
namespace {

using Clock = std::chrono::steady_clock;
double secondsSince(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

float floatBelow(double v) {
  const float f = static_cast<float>(v);
  return double(f) <= v ? f : std::nextafter(f, -std::numeric_limits<float>::infinity());
}
float floatAbove(double v) {
  const float f = static_cast<float>(v);
  return double(f) >= v ? f : std::nextafter(f, std::numeric_limits<float>::infinity());
}

// Breadth-first node list: roots row-major, then each level's children in SW, SE, NW, NE order.
std::vector<NodeRecord> enumerateNodes(const TreeLayout& layout) {
  std::vector<NodeRecord> nodes;
  for (int32_t y = 0; y < layout.rootsY; ++y)
    for (int32_t x = 0; x < layout.rootsX; ++x) {
      NodeRecord n;
      n.x = uint32_t(x);
      n.y = uint32_t(y);
      nodes.push_back(n);
    }
  for (size_t i = 0; i < nodes.size(); ++i) {
    if (nodes[i].level == layout.depth) continue;
    const int32_t level = nodes[i].level + 1;
    for (int q = 0; q < 4; ++q) {
      const int32_t cx = int32_t(nodes[i].x) * 2 + (q & 1), cy = int32_t(nodes[i].y) * 2 + (q >> 1);
      if (!layout.chunkExists(level, cx, cy)) continue;
      if (nodes[i].childMask == 0) nodes[i].firstChild = uint32_t(nodes.size());
      nodes[i].childMask |= uint8_t(1u << q);
      NodeRecord c;
      c.level = uint8_t(level);
      c.x = uint32_t(cx);
      c.y = uint32_t(cy);
      c.parent = uint32_t(i);
      nodes.push_back(c);
    }
  }
  return nodes;
}

Result<Heightfield> loadHeights(const DemReader& reader, Progress& progress) {
  const DemInfo& info = reader.info();
  Heightfield heights(info.columns, info.rows);
  constexpr int32_t kStrip = 256;
  progress.begin("reading", uint64_t(info.rows));
  for (int32_t y = 0; y < info.rows; y += kStrip) {
    const int32_t n = std::min(kStrip, info.rows - y);
    if (Status s = reader.readWindow(0, y, info.columns, n, heights.row(y)); !s) return s.error();
    progress.advance(uint64_t(n));
  }
  progress.end();
  return heights;
}

std::string metadataJson(const DemInfo& info, const BuildOptions& options, const BuildSummary& s,
                         const TreeLayout& layout) {
  nlohmann::json source = {
      {"file", std::filesystem::path(info.path).filename().string()},
      {"driver", info.driver},
      {"data_type", info.dataType},
      {"columns", info.columns},
      {"rows", info.rows},
      {"spacing", {info.spacingX, info.spacingY}},
      {"spacing_source", info.spacingSource},
      {"crs_wkt", info.crsWkt},
      {"encoding", info.encoding == HeightEncoding::kPlain        ? "none"
                   : info.encoding == HeightEncoding::kTerrainRgb ? "terrain-rgb"
                                                                  : "terrarium"},
  };
  if (info.hasGeoTransform) source["geotransform"] = info.geoTransform;
  if (info.nodata) source["nodata"] = *info.nodata;
  nlohmann::json j = {
      {"generator", "terralod"},
      {"source", source},
      {"build",
       {{"max_error", options.maxError},
        {"chunk_cells", layout.leafCells},
        {"vertical_scale", options.dem.verticalScale},
        {"zstd_level", options.compressionLevel}}},
      {"stats",
       {{"vertices", s.vertices},
        {"triangles", s.triangles},
        {"skirt_triangles", s.skirtTriangles},
        {"filled_voids", s.filledVoids}}},
  };
  return j.dump(2);
}

}  // namespace

Result<BuildSummary> buildTileset(const BuildOptions& options, Progress& progress,
                                  const std::function<void(const std::string&)>& warn) {
  const auto start = Clock::now();
  BuildSummary summary;
  auto opened = DemReader::open(options.input, options.dem);
  if (!opened) return opened.error();
  const DemReader& reader = **opened;
  const DemInfo& info = reader.info();
  summary.sourceSamples = uint64_t(info.columns) * uint64_t(info.rows);
  const unsigned threads = options.threads ? options.threads : hardwareThreads();

  auto layout = makeTreeLayout(info.columns, info.rows, options.chunkCells);
  if (!layout) return layout.error();
  // Fail on an unwritable output before doing any work.
  auto writer = TilesetWriter::create(options.output);
  if (!writer) return writer.error();

  const uint64_t heightBytes = summary.sourceSamples * sizeof(float);
  if (heightBytes > options.memoryMB * (uint64_t{1} << 20))
    return makeError(info.path, "the raster needs " + std::to_string(heightBytes >> 20) +
                                    " MB, more than --memory-mb " +
                                    std::to_string(options.memoryMB) +
                                    "; windowed builds are not available yet");

  auto loaded = loadHeights(reader, progress);
  if (!loaded) return loaded.error();
  Heightfield& heights = *loaded;
  auto filled = fillVoids(heights, info.path);
  if (!filled) return filled.error();
  summary.filledVoids = *filled;
  // Warn only once the input has proven usable, so a broken input gets its one error line.
  if (info.spacingAssumed) warn(info.path + ": " + info.spacingSource);
  double zMin = std::numeric_limits<double>::infinity(), zMax = -zMin;
  for (float v : heights.values()) {
    zMin = std::min(zMin, double(v));
    zMax = std::max(zMax, double(v));
  }
  if (!std::isfinite(zMin) || !std::isfinite(zMax))
    return makeError(info.path, "heights are not finite after filling voids");
  summary.loadSeconds = secondsSince(start);

  auto budget = makeErrorBudget(*layout, options.maxError, zMax - zMin);
  if (!budget) return makeError(info.path, budget.error().message);

  const auto errorStart = Clock::now();
  MemoryHeights memory(heights);
  ActivationOptions activationOptions;
  activationOptions.threads = threads;
  activationOptions.blockCells = 512;
  ActivationStats activationStats;
  auto grid = computeActivations(*layout, *budget, memory, memory, activationOptions, progress,
                                 &activationStats);
  if (!grid) return grid.error();
  summary.errorSeconds = secondsSince(errorStart);
  summary.trianglesScanned = activationStats.trianglesScanned;
  summary.trianglesBounded = activationStats.trianglesBounded;

  // Mesh, encode and write every chunk. Workers take chunks in node order; blobs are written in
  // node order too, so the file is the same whatever the thread count.
  const auto meshStart = Clock::now();
  std::vector<NodeRecord> nodes = enumerateNodes(*layout);
  std::vector<std::vector<uint8_t>> pending(nodes.size());
  std::vector<uint8_t> ready(nodes.size(), 0);
  size_t nextToWrite = 0;
  std::mutex writeMutex;
  std::optional<Error> failure;
  std::atomic<bool> failed{false};
  std::vector<std::unique_ptr<ChunkMesher>> meshers(threads);
  for (auto& m : meshers) m = std::make_unique<ChunkMesher>(*layout, *budget, *grid, memory);

  progress.begin("meshing", nodes.size());
  parallelFor(nodes.size(), threads, [&](size_t i, unsigned worker) {
    progress.advance();
    if (failed) return;
    NodeRecord& node = nodes[i];
    const ChunkMesh mesh = meshers[worker]->build(node.level, int32_t(node.x), int32_t(node.y));
    auto geometry = quantizeChunk(mesh, *budget);
    std::vector<uint8_t> blob;
    if (geometry) blob = encodeChunk(*geometry, options.compressionLevel);
    node.minZ = floatBelow(mesh.minZ);
    node.maxZ = floatAbove(mesh.maxZ);
    node.vertexCount = mesh.surfaceVertexCount;
    node.triangleCount = uint32_t(mesh.surfaceIndices.size() / 3);
    node.skirtTriangleCount = uint32_t(mesh.skirtIndices.size() / 3);
    node.maxSkirtDepth =
        floatAbove(*std::max_element(mesh.skirtDepth.begin(), mesh.skirtDepth.end()));
    node.blobBytes = uint32_t(blob.size());
    node.blobCrc = crc32Of(blob);

    std::lock_guard lock(writeMutex);
    if (!geometry) {
      failure = geometry.error();
      failed = true;
      return;
    }
    pending[i] = std::move(blob);
    ready[i] = 1;
    while (nextToWrite < nodes.size() && ready[nextToWrite]) {
      auto offset = (*writer)->appendBlob(pending[nextToWrite]);
      if (!offset) {
        failure = offset.error();
        failed = true;
        return;
      }
      nodes[nextToWrite].blobOffset = *offset;
      std::vector<uint8_t>().swap(pending[nextToWrite]);
      ++nextToWrite;
    }
  });
  progress.end();
  if (failure) return *failure;
  summary.meshSeconds = secondsSince(meshStart);

  for (const NodeRecord& n : nodes) {
    summary.vertices += n.vertexCount;
    summary.triangles += n.triangleCount;
    summary.skirtTriangles += n.skirtTriangleCount;
  }
  summary.levels = layout->levelCount();
  summary.chunks = nodes.size();

  TilesetHeader header;
  header.levelCount = uint32_t(layout->levelCount());
  header.leafCells = uint32_t(layout->leafCells);
  header.rootCells = uint32_t(layout->rootCells);
  header.rootsX = uint32_t(layout->rootsX);
  header.rootsY = uint32_t(layout->rootsY);
  header.sourceColumns = uint32_t(info.columns);
  header.sourceRows = uint32_t(info.rows);
  header.spacingX = info.spacingX;
  header.spacingY = info.spacingY;
  for (int32_t l = 0; l < layout->levelCount(); ++l)
    header.levelError[size_t(l)] = budget->levelError[size_t(l)];
  header.extentMin = {0.0, 0.0, zMin};
  header.extentMax = {layout->cellsX * info.spacingX, layout->cellsY * info.spacingY, zMax};
  header.filledVoids = summary.filledVoids;
  header.leafError = options.maxError;
  header.verticalScale = options.dem.verticalScale;
  if (Status s = (*writer)->finish(header, nodes, metadataJson(info, options, summary, *layout));
      !s)
    return s.error();
  std::error_code ec;
  summary.fileBytes = std::filesystem::file_size(options.output, ec);
  summary.totalSeconds = secondsSince(start);
  return summary;
}

}  // namespace terralod
