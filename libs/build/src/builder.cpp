#include "terralod/build/builder.h"

#include <algorithm>
#include <cassert>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <limits>
#include <memory>
#include <nlohmann/json.hpp>

#include "build_steps.h"
#include "load_heights.h"
#include "source_metadata.h"
#include "terralod/build/activation_pass.h"
#include "terralod/build/chunk_pass.h"
#include "terralod/build/dem_windows.h"
#include "terralod/build/error_budget.h"
#include "terralod/build/height_source.h"
#include "terralod/build/sparse_heights.h"
#include "terralod/build/tree_layout.h"
#include "terralod/build/vipm_builder.h"
#include "terralod/core/parallel.h"
#include "terralod/format/tileset_writer.h"
#include "terralod/raster/heightfield.h"
#include "terralod/raster/image_drape.h"
#include "terralod/raster/void_fill.h"

namespace terralod {
namespace {

using Clock = std::chrono::steady_clock;
double secondsSince(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

// Everything the two passes need to know about where heights come from.
struct HeightPlan {
  std::unique_ptr<Heightfield> memory;  // in-memory raster (voids filled)
  std::unique_ptr<MemoryHeights> memoryHeights;
  std::unique_ptr<SparseHeights> sparse;  // streamed raster
  std::unique_ptr<DemWindows> windows;
  double zMin = 0, zMax = 0;
  std::shared_ptr<const SampleMask> seaVoids;  // voids that were sea (in memory only)
};

Status loadIntoMemory(const DemReader& reader, Progress& progress, HeightPlan& plan,
                      BuildSummary& summary) {
  auto loaded = loadHeights(reader, progress);
  if (!loaded) return loaded.error();
  plan.memory = std::make_unique<Heightfield>(std::move(loaded).value());
  // Which voids were sea, for the generated colour, before filling them.
  if (SampleMask sea = seaVoids(*plan.memory); sea.count() > 0)
    plan.seaVoids = std::make_shared<const SampleMask>(std::move(sea));
  auto filled = fillVoids(*plan.memory, reader.info().path);
  if (!filled) return filled.error();
  summary.filledVoids = *filled;
  plan.zMin = std::numeric_limits<double>::infinity();
  plan.zMax = -plan.zMin;
  for (float v : plan.memory->values()) {
    plan.zMin = std::min(plan.zMin, double(v));
    plan.zMax = std::max(plan.zMax, double(v));
  }
  if (!std::isfinite(plan.zMin) || !std::isfinite(plan.zMax))
    return makeError(reader.info().path, "heights are not finite after filling voids");
  plan.memoryHeights = std::make_unique<MemoryHeights>(*plan.memory);
  return {};
}

}  // namespace

Result<BuildSummary> buildTileset(const BuildOptions& options, Progress& progress,
                                  const std::function<void(const std::string&)>& warn) {
  if (options.kind == TilesetKind::kVipm) return buildVipmTileset(options, progress, warn);
  assert(options.edits.empty());  // edits are for VIPM tilesets (terralod edit refuses others)
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
  if (options.textures && !(options.textureTau > 0 && std::isfinite(options.textureTau)))
    return Error{"--min-tau must be a positive number of pixels"};
  // A draped image is checked (readable, georeferenced, overlapping) before any work.
  std::unique_ptr<ImageDrape> image;
  if (options.textures && !options.textureImage.empty()) {
    auto drape = ImageDrape::open(options.textureImage, info);
    if (!drape) return drape.error();
    image = std::move(drape).value();
    summary.textureRefine = image->refine();
  }
  // Fail on an unwritable output before doing any work.
  auto writer = TilesetWriter::create(options.output);
  if (!writer) return writer.error();

  const bool fitsMemory = summary.sourceSamples * sizeof(float) <= options.memoryMB << 20;
  bool stream = streamsInput(options, info);
  if (!stream && !fitsMemory)
    return makeError(info.path,
                     "the raster needs " + std::to_string((summary.sourceSamples * 4) >> 20) +
                         " MB, more than --memory-mb " + std::to_string(options.memoryMB));

  ActivationOptions activationOptions;
  activationOptions.threads = threads;
  activationOptions.blockCells =
      std::clamp(options.blockCells, layout->leafCells, layout->rootCells);
  HeightPlan plan;
  Result<ErrorBudget> budget = Error{};
  Result<ActivationGrid> grid = Error{};
  ActivationStats activationStats;

  if (stream) {
    // Pass 1 reads the raster block by block. Its thresholds depend on the height range,
    // which is estimated first and checked once every sample has been seen.
    auto [guessLo, guessHi] = guessHeightRange(reader);
    plan.sparse = std::make_unique<SparseHeights>(*layout, activationOptions.blockCells);
    plan.windows = std::make_unique<DemWindows>(reader, threads, plan.sparse.get());
    for (int attempt = 0; attempt < 2; ++attempt) {
      budget = makeErrorBudget(*layout, options.maxError, guessHi - guessLo);
      if (!budget) return makeError(info.path, budget.error().message);
      const auto errorStart = Clock::now();
      activationStats = {};
      grid = computeActivations(*layout, *budget, *plan.windows, *plan.sparse, activationOptions,
                                progress, &activationStats);
      if (!grid) return grid.error();
      summary.errorSeconds += secondsSince(errorStart);
      ++summary.errorPasses;
      if (plan.windows->sawVoid()) break;
      plan.zMin = plan.windows->minHeight();
      plan.zMax = plan.windows->maxHeight();
      if (plan.zMin >= guessLo && plan.zMax <= guessHi) break;
      guessLo = plan.zMin;
      guessHi = plan.zMax;
    }
    if (plan.windows->sawVoid()) {
      if (!fitsMemory)
        return makeError(info.path, "has voids and is larger than --memory-mb " +
                                        std::to_string(options.memoryMB) +
                                        "; filling voids out of core is not supported yet "
                                        "(fill them first, e.g. with gdal_fillnodata)");
      stream = false;  // voids need the whole raster to be filled: start over in memory
      plan = HeightPlan{};
    } else {
      plan.windows->stopRecording();
    }
  }
  if (!stream) {
    if (Status s = loadIntoMemory(reader, progress, plan, summary); !s) return s.error();
    summary.loadSeconds = secondsSince(start);
    budget = makeErrorBudget(*layout, options.maxError, plan.zMax - plan.zMin);
    if (!budget) return makeError(info.path, budget.error().message);
    const auto errorStart = Clock::now();
    grid = computeActivations(*layout, *budget, *plan.memoryHeights, *plan.memoryHeights,
                              activationOptions, progress, &activationStats);
    if (!grid) return grid.error();
    summary.errorSeconds = secondsSince(errorStart);
    summary.errorPasses = 1;
  }
  summary.streamed = stream;
  summary.trianglesScanned = activationStats.trianglesScanned;
  summary.trianglesBounded = activationStats.trianglesBounded;
  // Warn only once the input has proven usable, so a broken input gets its one error line.
  warnAboutSource(info, warn);

  const auto meshStart = Clock::now();
  std::vector<NodeRecord> nodes = enumerateNodes(*layout);
  ChunkPassOptions chunkOptions;
  chunkOptions.blockCells = activationOptions.blockCells;
  chunkOptions.threads = threads;
  chunkOptions.compressionLevel = options.compressionLevel;
  TextureBuild textures;
  if (options.textures) {
    textures = textureBuildFor(options, *layout, *budget, reader, image.get());
    textures.surface.seaVoids = plan.seaVoids;
    chunkOptions.textures = &textures;
  }
  HeightWindows& windows = stream ? static_cast<HeightWindows&>(*plan.windows)
                                  : static_cast<HeightWindows&>(*plan.memoryHeights);
  if (Status s = buildChunks(
          *layout, *budget, *grid, nodes, windows, stream ? nullptr : plan.memoryHeights.get(),
          stream ? plan.sparse.get() : nullptr, chunkOptions, **writer, progress);
      !s)
    return s.error();
  summary.meshSeconds = secondsSince(meshStart);

  summarizeNodes(nodes, summary);
  summary.levels = layout->levelCount();
  const TilesetHeader header =
      staticHeader(info, options, *layout, *budget, plan.zMin, plan.zMax, summary.filledVoids);
  if (Status s = (*writer)->finish(header, nodes,
                                   tilesetMetadataJson(info, options, summary, *layout,
                                                       options.textures ? &textures : nullptr));
      !s)
    return s.error();
  std::error_code ec;
  summary.fileBytes = std::filesystem::file_size(options.output, ec);
  summary.totalSeconds = secondsSince(start);
  return summary;
}

}  // namespace terralod
