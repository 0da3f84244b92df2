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
#include "terralod/build/kept_heights.h"
#include "terralod/build/leaf_size.h"
#include "terralod/build/pass_one_textures.h"
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
  std::unique_ptr<KeptHeights> kept;      // streamed, RTIN: what pass 2 reads, read once
  std::unique_ptr<DemWindows> windows;
  // Streamed, textured, within the memory budget: the textures made in pass 1 from its
  // windows, so that pass 2 needs only `kept` (the raster is not kept whole).
  std::unique_ptr<TextureBuild> textureBuild;
  std::unique_ptr<PassOneTextures> passOneTextures;
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

// What the build works from once the request has been checked.
struct LocalBuild {
  std::unique_ptr<DemReader> reader;
  TreeLayout layout;
  std::unique_ptr<ImageDrape> image;  // null: the generated colour (or no textures)
  std::unique_ptr<TilesetWriter> writer;
  unsigned threads = 1;
  int32_t block = 512;
  bool fitsMemory = false;
};

// Opens the DEM and the draped image and creates the output, so that every problem with the
// request is reported before any work.
Result<LocalBuild> openBuild(const BuildOptions& options, BuildSummary& summary) {
  LocalBuild b;
  auto opened = DemReader::open(options.input, options.dem);
  if (!opened) return opened.error();
  b.reader = std::move(opened).value();
  const DemInfo& info = b.reader->info();
  summary.sourceSamples = uint64_t(info.columns) * uint64_t(info.rows);
  b.threads = options.threads ? options.threads : hardwareThreads();
  // The raster's size and an explicit --chunk-cells are checked here; an automatic leaf size
  // is chosen last, since it reads some of the raster.
  if (auto layout = makeTreeLayout(info.columns, info.rows, options.chunkCells); !layout)
    return layout.error();
  if (options.textures && !(options.textureTau > 0 && std::isfinite(options.textureTau)))
    return Error{"--min-tau must be a positive number of pixels"};
  // A draped image is checked (readable, georeferenced, overlapping) before any work.
  if (options.textures && !options.textureImage.empty()) {
    auto drape = ImageDrape::open(options.textureImage, info);
    if (!drape) return drape.error();
    b.image = std::move(drape).value();
    summary.textureRefine = b.image->refine();
  }
  auto writer = TilesetWriter::create(options.output);
  if (!writer) return writer.error();
  b.writer = std::move(writer).value();
  b.fitsMemory = summary.sourceSamples * sizeof(float) <= options.memoryMB << 20;
  if (!streamsInput(options, info) && !b.fitsMemory)
    return makeError(info.path,
                     "the raster needs " + std::to_string((summary.sourceSamples * 4) >> 20) +
                         " MB, more than --memory-mb " + std::to_string(options.memoryMB));
  auto leafCells = leafCellsFor(options, *b.reader);
  if (!leafCells) return leafCells.error();
  auto layout = makeTreeLayout(info.columns, info.rows, *leafCells);
  if (!layout) return layout.error();
  b.layout = *layout;
  b.block = std::clamp(options.blockCells, b.layout.leafCells, b.layout.rootCells);
  return b;
}

// Pass 1's result.
struct ErrorPass {
  ErrorBudget budget;
  ActivationGrid grid;
};

// Pass 1 over a streamed raster: the budget from the height estimate, again with the true range
// when the data leave it. Leaves `plan` empty when the raster has voids (they need it whole).
Result<ErrorPass> streamedErrors(const BuildOptions& options, const LocalBuild& b,
                                 const std::vector<NodeRecord>& nodes, HeightPlan& plan,
                                 Progress& progress, BuildSummary& summary) {
  const DemInfo& info = b.reader->info();
  ActivationOptions activation{b.block, b.threads};
  auto [guessLo, guessHi] = guessHeightRange(*b.reader);
  plan.sparse = std::make_unique<SparseHeights>(b.layout, b.block);
  plan.windows = std::make_unique<DemWindows>(*b.reader, b.threads, plan.sparse.get());
  // Within the memory budget, pass 1 keeps what it reads and pass 2 reads memory: one decode
  // of the raster instead of two. (--streaming always keeps nothing.) With RTIN chunks, pass 2
  // reads only the vertices and the chunk sides: pass 1 keeps just those, for a raster of any
  // size, as long as they fit the budget; a textured build then makes its textures in pass 1
  // when the raster and the texture blocks, which are held until pass 2 writes them, both fit.
  const bool automatic = options.streaming == Streaming::kAuto;
  const bool rtin = options.mesher == MeshMethod::kRtin;
  if (automatic && rtin && options.textures && b.fitsMemory) {
    // The textures depend on the heights and the levels' errors, not on the height range.
    auto levels = makeErrorBudget(b.layout, options.maxError, guessHi - guessLo);
    if (!levels) return makeError(info.path, levels.error().message);
    auto build = std::make_unique<TextureBuild>(textureBuildFor(
        options, b.layout, *levels, sourceFactsOf(*b.reader, b.image.get()), b.image.get()));
    if (PassOneTextures::blockBytes(*build, nodes) <= options.memoryMB << 20)
      plan.textureBuild = std::move(build);
  }
  if (automatic && rtin && (!options.textures || plan.textureBuild)) {
    plan.kept = std::make_unique<KeptHeights>(b.layout, b.block, options.memoryMB << 20);
    activation.keep = plan.kept.get();
  } else if (automatic && b.fitsMemory) {
    plan.memory = std::make_unique<Heightfield>(info.columns, info.rows);
  }
  Result<ErrorPass> pass = Error{};
  for (int attempt = 0; attempt < 2; ++attempt) {
    auto budget = makeErrorBudget(b.layout, options.maxError, guessHi - guessLo);
    if (!budget) return makeError(info.path, budget.error().message);
    if (plan.memory) plan.windows->keepInto(*plan.memory);
    if (attempt == 0 && plan.textureBuild) {  // made once, in the first attempt
      plan.passOneTextures = std::make_unique<PassOneTextures>(b.layout, *plan.textureBuild, nodes,
                                                               b.block, b.threads);
      if (Status s = plan.passOneTextures->open(); !s) return s.error();
      activation.user = plan.passOneTextures.get();
    }
    const auto errorStart = Clock::now();
    ActivationStats stats;
    auto grid = computeActivations(b.layout, *budget, *plan.windows, *plan.sparse, activation,
                                   progress, &stats);
    if (!grid) return grid.error();
    summary.errorSeconds += secondsSince(errorStart);
    ++summary.errorPasses;
    summary.trianglesScanned = stats.trianglesScanned;
    summary.trianglesBounded = stats.trianglesBounded;
    pass = ErrorPass{std::move(budget).value(), std::move(grid).value()};
    activation.user = nullptr;
    if (plan.windows->sawVoid()) break;
    plan.zMin = plan.windows->minHeight();
    plan.zMax = plan.windows->maxHeight();
    if (plan.zMin >= guessLo && plan.zMax <= guessHi) break;
    guessLo = plan.zMin;
    guessHi = plan.zMax;
  }
  if (plan.windows->sawVoid()) {
    if (!b.fitsMemory)
      return makeError(info.path, "has voids and is larger than --memory-mb " +
                                      std::to_string(options.memoryMB) +
                                      "; filling voids out of core is not supported yet "
                                      "(fill them first, e.g. with gdal_fillnodata)");
    plan = HeightPlan{};  // voids need the whole raster to be filled: start over in memory
    summary.errorPasses = 0;
    return pass;
  }
  plan.windows->stopRecording();
  if (plan.memory && plan.windows->keptAll())
    plan.memoryHeights = std::make_unique<MemoryHeights>(*plan.memory);
  else
    plan.memory.reset();
  if (plan.kept && !plan.kept->keptAll()) plan.kept.reset();
  return pass;
}

// Pass 1 over the raster in memory (voids filled).
Result<ErrorPass> inMemoryErrors(const BuildOptions& options, const LocalBuild& b, HeightPlan& plan,
                                 Progress& progress, BuildSummary& summary,
                                 Clock::time_point start) {
  if (Status s = loadIntoMemory(*b.reader, progress, plan, summary); !s) return s.error();
  summary.loadSeconds = secondsSince(start);
  auto budget = makeErrorBudget(b.layout, options.maxError, plan.zMax - plan.zMin);
  if (!budget) return makeError(b.reader->info().path, budget.error().message);
  const auto errorStart = Clock::now();
  ActivationStats stats;
  auto grid = computeActivations(b.layout, *budget, *plan.memoryHeights, *plan.memoryHeights,
                                 ActivationOptions{b.block, b.threads}, progress, &stats);
  if (!grid) return grid.error();
  summary.errorSeconds = secondsSince(errorStart);
  summary.errorPasses = 1;
  summary.trianglesScanned = stats.trianglesScanned;
  summary.trianglesBounded = stats.trianglesBounded;
  return ErrorPass{std::move(budget).value(), std::move(grid).value()};
}

}  // namespace

Result<BuildSummary> buildTileset(const BuildOptions& options, Progress& progress,
                                  const std::function<void(const std::string&)>& warn) {
  if (options.kind == TilesetKind::kVipm) return buildVipmTileset(options, progress, warn);
  assert(options.edits.empty());  // edits are for VIPM tilesets (terralod edit refuses others)
  const auto start = Clock::now();
  BuildSummary summary;
  auto opened = openBuild(options, summary);
  if (!opened) return opened.error();
  LocalBuild& b = *opened;
  const DemInfo& info = b.reader->info();

  // Pass 1: errors into activations (and, streamed, maybe the textures).
  std::vector<NodeRecord> nodes = enumerateNodes(b.layout);
  HeightPlan plan;
  Result<ErrorPass> pass = Error{};
  summary.streamed = streamsInput(options, info);
  if (summary.streamed) {
    pass = streamedErrors(options, b, nodes, plan, progress, summary);
    if (!pass) return pass.error();
    summary.streamed = plan.windows != nullptr;  // false: voids, so in memory after all
    summary.readOnce = summary.streamed && (plan.memoryHeights || plan.kept);
    if (plan.kept) summary.keptSamples = plan.kept->keptSamples();
  }
  if (!summary.streamed) {
    pass = inMemoryErrors(options, b, plan, progress, summary, start);
    if (!pass) return pass.error();
  }
  // Warn only once the input has proven usable, so a broken input gets its one error line.
  warnAboutSource(info, warn);

  // Pass 2: chunks and textures.
  const auto meshStart = Clock::now();
  ChunkPassOptions chunkOptions;
  chunkOptions.blockCells = b.block;
  chunkOptions.threads = b.threads;
  chunkOptions.compressionLevel = options.compressionLevel;
  chunkOptions.mesher = options.mesher;
  chunkOptions.payload = chunkPayloadOf(options);
  TextureBuild textures;
  std::vector<std::vector<uint8_t>> madeTextures;  // by node, when pass 1 made them
  if (plan.passOneTextures) {
    auto made = plan.passOneTextures->take();
    if (!made) return made.error();
    madeTextures = std::move(made).value();
    plan.passOneTextures.reset();
    textures = *plan.textureBuild;
    chunkOptions.madeTextures = &madeTextures;
  } else if (options.textures) {
    textures = textureBuildFor(options, b.layout, pass->budget,
                               sourceFactsOf(*b.reader, b.image.get()), b.image.get());
    textures.surface.seaVoids = plan.seaVoids;
    chunkOptions.textures = &textures;
  }
  // Pass 2 reads memory when the raster is there (loaded whole, or kept by pass 1).
  const bool inMemory = plan.memoryHeights != nullptr;
  HeightWindows& windows = inMemory ? static_cast<HeightWindows&>(*plan.memoryHeights)
                                    : static_cast<HeightWindows&>(*plan.windows);
  const HeightSampler* allHeights =
      inMemory ? static_cast<const HeightSampler*>(plan.memoryHeights.get()) : plan.kept.get();
  if (Status s =
          buildChunks(b.layout, pass->budget, pass->grid, nodes, windows, allHeights,
                      allHeights ? nullptr : plan.sparse.get(), chunkOptions, *b.writer, progress);
      !s)
    return s.error();
  if (plan.kept && plan.kept->misses() > 0)
    return Error{"internal error: " + std::to_string(plan.kept->misses()) +
                 " heights were needed that pass 1 had not kept"};
  summary.meshSeconds = secondsSince(meshStart);

  if (options.textures) markInheritedTextures(textures.plan, nodes);
  summarizeNodes(nodes, summary);
  summary.levels = b.layout.levelCount();
  const TilesetHeader header = staticHeader(info, options, b.layout, pass->budget, plan.zMin,
                                            plan.zMax, summary.filledVoids);
  if (Status s = b.writer->finish(header, nodes,
                                  tilesetMetadataJson(info, options, summary, b.layout,
                                                      options.textures ? &textures : nullptr));
      !s)
    return s.error();
  std::error_code ec;
  summary.fileBytes = std::filesystem::file_size(options.output, ec);
  summary.totalSeconds = secondsSince(start);
  return summary;
}

}  // namespace terralod
