#include "terralod/build/build_stages.h"

#include <sys/resource.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <mutex>
#include <optional>
#include <sstream>
#include <unordered_map>

#include "block_stages.h"
#include "build_steps.h"
#include "source_metadata.h"
#include "stage_files.h"
#include "stage_records.h"
#include "stage_work.h"
#include "terralod/build/chunk_pass.h"
#include "terralod/build/dem_windows.h"
#include "terralod/build/kept_heights.h"
#include "terralod/build/leaf_size.h"
#include "terralod/build/sparse_heights.h"
#include "terralod/build/surface_texels.h"
#include "terralod/build/tile_pyramid.h"
#include "terralod/core/atomic_file.h"
#include "terralod/core/parallel.h"
#include "terralod/format/tileset_writer.h"
#include "terralod/raster/image_drape.h"

namespace terralod {

using namespace stages;
namespace fs = std::filesystem;

// ---- Stages ------------------------------------------------------------------------------

Result<BuildPlan> planStage(const BuildOptions& options, const std::string& work, int jobs,
                            Progress& progress, const Warn& warn) {
  if (options.kind != TilesetKind::kStatic)
    return Error{"a staged build makes static tilesets (VIPM builds do not stage yet)"};
  if (jobs < 0) return Error{"--jobs must be at least 1"};
  BuildPlan plan;
  plan.options = options;
  plan.options.input = absolute(options.input);
  plan.options.output = absolute(options.output);
  plan.options.textureImage = absolute(options.textureImage);
  auto opened = DemReader::open(plan.options.input, options.dem);
  if (!opened) return opened.error();
  const DemReader& reader = **opened;
  const DemInfo& info = reader.info();
  if (auto checked = makeTreeLayout(info.columns, info.rows, options.chunkCells); !checked)
    return checked.error();
  if (options.textures && !(options.textureTau > 0 && std::isfinite(options.textureTau)))
    return Error{"--min-tau must be a positive number of pixels"};
  auto image = openImage(plan.options, info);
  if (!image) return image.error();
  plan.source = sourceFactsOf(reader, image->get());
  // Fail on an unwritable output before any job runs.
  if (auto writer = TilesetWriter::create(plan.options.output); !writer) return writer.error();
  if (Status s = checkWorkDirectory(work); !s) return s.error();
  // The plan records the leaf size, so that every job makes the same tree (an automatic one
  // reads some of the raster, so it comes after the checks).
  auto leafCells = leafCellsFor(options, reader);
  if (!leafCells) return leafCells.error();
  plan.options.chunkCells = *leafCells;
  auto layout = makeTreeLayout(info.columns, info.rows, *leafCells);
  if (!layout) return layout.error();

  plan.blockCells = std::clamp(options.blockCells, layout->leafCells, layout->rootCells);
  // The budget's height range as a local build would take it: the data's own when it would
  // read the raster whole (read here, in strips), else the estimate a streamed build starts
  // from.
  plan.exactRange = !streamsInput(options, info);
  auto range = plan.exactRange ? exactHeightRange(reader, progress)
                               : Result<std::array<double, 2>>(guessHeightRange(reader));
  if (!range) return range.error();
  plan.heightLo = (*range)[0];
  plan.heightHi = (*range)[1];
  if (auto budget = makeErrorBudget(*layout, options.maxError, plan.heightHi - plan.heightLo);
      !budget)
    return makeError(info.path, budget.error().message);
  const std::vector<NodeRecord> nodes = enumerateNodes(*layout);
  for (uint32_t n : blockNodesOf(nodes, blockLevelOf(*layout, plan.blockCells)))
    plan.blocks.push_back({int32_t(nodes[n].x), int32_t(nodes[n].y)});
  // Default: one job per block, at most 64.
  plan.jobs = std::min<int>(jobs > 0 ? jobs : 64, int(plan.blocks.size()));
  warnAboutSource(info, warn);
  cleanWorkDirectory(work);
  if (Status s = makeDirectories(work); !s) return s.error();
  if (Status s = writeText(planPath(work), buildPlanJson(plan)); !s) return s.error();
  return plan;
}

namespace {

// What a pass-1 job of an RTIN build makes for its pass-2 job and assemble besides its
// activations: each block's kept heights and, textured, its textures (from the windows with the
// texture pass's margin), so that pass 2 reads no DEM. The textures above the job's blocks that
// need no other job's are built here too (whole subtrees), the rest handed on as its frontier.
class PassOneOutputs {
 public:
  PassOneOutputs(const std::string& work, const StageContext& s, int job, unsigned threads)
      : mWork(work),
        mS(s),
        mJob(job),
        mThreads(threads),
        mKept(s.layout, s.block, UINT64_MAX),
        mKeptRecords(s.plan.jobBlocks(job)[1] - s.plan.jobBlocks(job)[0]) {}

  Status open() {
    const BuildOptions& o = mS.plan.options;
    if (!o.textures) return {};
    auto image = openImage(o, mS.info());
    if (!image) return image.error();
    mImage = std::move(image).value();
    mBuild = textureBuildFor(o, mS.layout, mS.budget, mS.plan.source, mImage.get());
    mPass = std::make_unique<TexturePass>(mS.layout, mBuild, mS.nodes, mThreads);
    if (Status st = mPass->open(); !st) return st;
    auto file = StageFileWriter::create(chunkTextures(mWork, mJob), StageFile::kChunkTextures);
    if (!file) return file.error();
    mChunkTextures.emplace(std::move(*file));
    mPyramid.emplace(
        *mPass, mS.nodes,
        TilePyramid::buildableFrom(mS.nodes, blockLevelOf(mS.layout, mS.block),
                                   jobBlockNodes(mS, mJob)),
        [this](uint32_t node, std::vector<uint8_t> texture) { mSpool.add(node, texture); });
    return {};
  }
  /// The texture pass's margin around each block's window (0 untextured).
  int32_t margin() const { return mPass ? BlockTexels::kMargin : 0; }

  /// Block `k` of the plan (the job's i-th): `window` its window with margin(), `closed` its
  /// closed square, `grid` its pass-1 activations. Thread-safe for distinct blocks.
  Status add(size_t k, size_t i, const BlockWindow& window, const float* closed,
             const ActivationGrid& grid, unsigned worker) {
    const GridPoint origin = mS.origin(k);
    mKept.keepBlock(origin, closed, grid);
    mKeptRecords[i] = packKept(mKept, origin);
    mKept.dropBlock(origin);
    if (!mPass) return {};
    const uint32_t blockNode = mS.blockNodes[k];
    std::vector<std::pair<uint32_t, std::vector<uint8_t>>> blobs;
    auto tiles = blockTexturesFrom(*mPass, blockNode, window, worker, blobs);
    if (!tiles) return tiles.error();
    std::unordered_map<uint32_t, size_t> of;
    for (size_t b = 0; b < blobs.size(); ++b) of.emplace(blobs[b].first, b);
    Packer piece;
    for (const uint32_t node : chunksBelow(mS.nodes, blockNode)) {
      const auto b = of.find(node);
      if (b == of.end()) return Error{"internal error: the texture pass left a chunk out"};
      piece.put(node);
      piece.putBytes(blobs[b->second].second);
    }
    mChunkTextures->put(i, std::move(piece.bytes()));
    mSpool.add(blockNode, blobs[of.at(blockNode)].second);
    mPyramid->add(blockNode, std::move(tiles).value());
    return {};
  }

  Status write() {
    if (Status st =
            writeBlockRecords(keptHeights(mWork, mJob), StageFile::kKeptHeights, mKeptRecords);
        !st)
      return st;
    if (!mPass) return {};
    if (Status st = mChunkTextures->commit(mKeptRecords.size()); !st) return st;
    const BuildOptions& o = mS.plan.options;
    if (Status st = mSpool.writeSorted(jobTextures(mWork, o, mJob)); !st) return st;
    return writeStageFile(jobTiles(mWork, o, mJob), StageFile::kJobTiles,
                          packFrontier(mPyramid->takeFrontier()));
  }

 private:
  const std::string& mWork;
  const StageContext& mS;
  int mJob;
  unsigned mThreads;
  KeptHeights mKept;
  std::vector<std::vector<uint8_t>> mKeptRecords;
  std::unique_ptr<ImageDrape> mImage;
  TextureBuild mBuild;
  std::unique_ptr<TexturePass> mPass;
  std::optional<OrderedStageWriter> mChunkTextures;
  TextureSpool mSpool;
  std::optional<TilePyramid> mPyramid;
};

}  // namespace

Status pass1Stage(const std::string& work, int job, unsigned threads, Progress& progress) {
  auto stage = loadStage(work);
  if (!stage) return stage.error();
  const StageContext& s = *stage;
  if (Status st = checkJob(s, job, work); !st) return st;
  threads = std::max(1u, threads);
  std::optional<PassOneOutputs> outputs;
  if (passOneKeeps(s.plan.options)) {
    outputs.emplace(work, s, job, threads);
    if (Status st = outputs->open(); !st) return st;
  }
  const int32_t margin = outputs ? outputs->margin() : 0;
  const HaloPattern halo = blockHalo(s.layout, s.block);
  auto reader = openStageDem(s, work);
  if (!reader) return reader.error();
  DemWindows windows(**reader, threads, nullptr);
  std::vector<BlockScratch> scratch(threads);
  std::vector<BlockWindow> margined(threads);
  std::vector<std::vector<float>> heights(threads);
  const auto range = s.plan.jobBlocks(job);
  std::vector<std::vector<uint8_t>> grids(range[1] - range[0]), halos(grids.size());
  progress.begin("errors", range[1] - range[0]);
  Status done = forBlocks(range, threads, [&](size_t k, unsigned w) -> Status {
    const GridPoint o = s.origin(k);
    const size_t side = size_t(s.block) + 1;
    heights[w].resize(side * side);
    BlockWindow& window = margined[w];
    window.x0 = o.x;
    window.y0 = o.y;
    window.cells = s.block;
    window.margin = margin;
    if (Status st =
            readWithMargin(windows, o.x, o.y, s.block, margin, window.values, heights[w].data(), w);
        !st)
      return st;
    const Pass1Block p = pass1Block(s.layout, s.budget, o, s.block, heights[w].data(), scratch[w]);
    Pass1Halo h;
    h.minHeight = p.minHeight;
    h.maxHeight = p.maxHeight;
    h.sawVoid = p.sawVoid;
    h.scanned = p.stats.trianglesScanned;
    h.bounded = p.stats.trianglesBounded;
    h.square = p.square;
    h.halo = haloValues(p.grid, halo);
    h.lines = linesOf(s.layout, o, s.block, heights[w].data());
    grids[k - range[0]] = compressedRecord(p.grid.nibbles());
    halos[k - range[0]] = packPass1Halo(h);
    if (outputs)
      if (Status st = outputs->add(k, k - range[0], window, heights[w].data(), p.grid, w); !st)
        return st;
    progress.advance();
    return {};
  });
  progress.end();
  if (!done) return done;
  if (Status st = writeBlockRecords(pass1Grids(work, job), StageFile::kPass1Grids, grids); !st)
    return st;
  if (Status st = writeBlockRecords(pass1Halos(work, job), StageFile::kPass1Halos, halos); !st)
    return st;
  return outputs ? outputs->write() : Status{};
}

Result<ReduceResult> reduceStage(const std::string& work, Progress& progress) {
  auto stage = loadStage(work);
  if (!stage) return stage.error();
  const StageContext& s = *stage;
  HaloStore store(s.layout, s.block);
  SparseHeights lines(s.layout, s.block);
  std::vector<BlockSquare> squares(store.blockCount());
  double zMin = std::numeric_limits<double>::infinity(), zMax = -zMin;
  progress.begin("borders", s.plan.blocks.size());
  for (int job = 0; job < s.plan.jobs; ++job) {
    const auto range = s.plan.jobBlocks(job);
    const std::string path = pass1Halos(work, job);
    auto records = BlockRecords::read(path, StageFile::kPass1Halos, range[1] - range[0]);
    if (!records) return records.error();
    for (size_t k = range[0]; k < range[1]; ++k) {
      auto h = unpackPass1Halo((*records)[k - range[0]], path);
      if (!h) return h.error();
      if (h->sawVoid) return makeError(s.plan.options.input, kVoidsRefused);
      const size_t b = s.gridBlock(k);
      if (h->halo.size() != store.values(b).size())
        return makeError(path, "was written for another block layout");
      store.values(b) = std::move(h->halo);
      squares[b] = h->square;
      recordLines(lines, h->lines);
      zMin = std::min(zMin, h->minHeight);
      zMax = std::max(zMax, h->maxHeight);
      progress.advance();
    }
  }
  progress.end();
  if (!s.plan.exactRange && s.plan.attempt == 0 &&
      (zMin < s.plan.heightLo || zMax > s.plan.heightHi)) {
    // The estimate was wrong: pass 1 again with the true range, as a local build's second
    // attempt.
    BuildPlan again = s.plan;
    again.attempt = 1;
    again.heightLo = zMin;
    again.heightHi = zMax;
    // Pass 1's tasks must run again: their ends no longer count.
    std::error_code ec;
    for (int t = 0; t < s.plan.jobs; ++t)
      fs::remove(taskStatusPath(work, BuildStage::kPass1, t, "ok"), ec);
    if (Status st = writeText(planPath(work), buildPlanJson(again)); !st) return st.error();
    return ReduceResult::kReplanned;
  }
  store.mergeBorders();
  finishBorders(s.layout, s.budget, lines, store, s.block, squares);
  if (store.misses() > 0 || lines.misses() > 0)
    return Error{"internal error: the border reduce reached " + std::to_string(store.misses()) +
                 " points outside the halos and " + std::to_string(lines.misses()) +
                 " heights off the block lines"};
  for (int job = 0; job < s.plan.jobs; ++job) {
    const auto range = s.plan.jobBlocks(job);
    std::vector<std::vector<uint8_t>> halos;
    for (size_t k = range[0]; k < range[1]; ++k) halos.push_back(store.values(s.gridBlock(k)));
    if (Status st = writeBlockRecords(reducedHalos(work, job), StageFile::kReducedHalos, halos);
        !st)
      return st.error();
  }
  // Halo points the coarse levels use (blocks without data have nothing else).
  const uint8_t coarse = s.budget.activationForLevel(blockLevelOf(s.layout, s.block));
  Packer p;
  p.put(zMin);
  p.put(zMax);
  std::vector<std::pair<uint64_t, uint8_t>> points;
  const uint32_t stride = uint32_t(s.block) + 1;
  for (size_t b = 0; b < store.blockCount(); ++b) {
    const GridPoint o = store.origin(b);
    const auto& halo = store.pattern(b).points;
    for (size_t i = 0; i < halo.size(); ++i)
      if (store.values(b)[i] >= coarse)
        points.emplace_back(
            ActivationGrid::key(o.x + int32_t(halo[i] % stride), o.y + int32_t(halo[i] / stride)),
            store.values(b)[i]);
  }
  p.putKeyed(points);
  if (Status st = writeStageFile(coarsePoints(work), StageFile::kCoarsePoints, p.bytes()); !st)
    return st.error();
  return ReduceResult::kDone;
}

namespace {

Result<StageContext> loadJobStage(const std::string& work, int job) {
  auto stage = loadStage(work);
  if (!stage) return stage.error();
  if (Status st = checkJob(*stage, job, work); !st) return st.error();
  return stage;
}

// Pass 2 of job `job` with the tree `nodes` (the stage's, moved: nothing below reads the
// stage's own, and the tree is the largest thing a pass-2 job of a large raster holds).
// `texturePass` makes the textures when pass 1 did not; `windows` gives the heights when pass 1
// kept none.
Status pass2Blocks(const std::string& work, int job, unsigned threads, const StageContext& s,
                   std::vector<NodeRecord>& nodes, TexturePass* texturePass, HeightWindows& windows,
                   Progress& progress) {
  const BuildOptions& o = s.plan.options;
  const std::vector<uint32_t>& blockNodes = s.blockNodes;
  const bool keeps = passOneKeeps(o);  // heights from pass 1, textures made there
  const int32_t blockLevel = blockLevelOf(s.layout, s.block);
  ChunkPassContext context{
      s.layout, s.budget,           nodes,
      s.block,  o.compressionLevel, texturePass,
      o.mesher, chunkPayloadOf(o),  firstGreedyLevel(blockLevel, CoarseHeights::kSparse)};
  const uint8_t coarse = s.budget.activationForLevel(blockLevel);
  std::vector<BlockWindow> heights(threads);
  const NoHeights none;
  const auto range = s.plan.jobBlocks(job);
  const size_t blocks = range[1] - range[0];
  auto grids = BlockRecords::read(pass1Grids(work, job), StageFile::kPass1Grids, blocks);
  if (!grids) return grids.error();
  auto reduced = BlockRecords::read(reducedHalos(work, job), StageFile::kReducedHalos, blocks);
  if (!reduced) return reduced.error();
  // The heights pass 1 kept, a block at a time per thread (a store holding one block answers
  // its whole closed square), so that a job of any size holds one block's per thread.
  const std::string keptPath = keptHeights(work, job);
  std::optional<BlockRecords> keptRecords;
  std::vector<std::unique_ptr<KeptHeights>> kept;
  if (keeps) {
    auto records = BlockRecords::read(keptPath, StageFile::kKeptHeights, blocks);
    if (!records) return records.error();
    keptRecords.emplace(std::move(*records));
    for (unsigned t = 0; t < threads; ++t)
      kept.push_back(std::make_unique<KeptHeights>(s.layout, s.block, UINT64_MAX));
  }
  // The chunks go to their file block by block as they are made (in the blocks' order),
  // never all of a job's at once: with a texture per chunk they are most of its output.
  auto chunkFile = StageFileWriter::create(pass2Chunks(work, job), StageFile::kChunks);
  if (!chunkFile) return chunkFile.error();
  OrderedStageWriter chunks(std::move(*chunkFile));
  std::vector<std::vector<uint8_t>> coarseRecords(blocks);
  // The textures above this job's blocks that need no other job's (whole subtrees), and the
  // block nodes' own. Their blobs wait in a temporary file, not in memory.
  std::optional<TilePyramid> pyramid;
  TextureSpool spool;
  if (texturePass)
    pyramid.emplace(
        *texturePass, nodes,
        TilePyramid::buildableFrom(nodes, blockLevelOf(s.layout, s.block), jobBlockNodes(s, job)),
        [&spool](uint32_t node, std::vector<uint8_t> texture) { spool.add(node, texture); });
  const HaloPattern halo = blockHalo(s.layout, s.block);
  progress.begin("meshing", range[1] - range[0]);
  Status done = forBlocks(range, threads, [&](size_t k, unsigned w) -> Status {
    const GridPoint origin = s.origin(k);
    const size_t i = k - range[0];
    ActivationGrid grid = ActivationGrid::window(origin.x, origin.y, s.block, s.block);
    if (Status st = decompressRecord((*grids)[i], grid.nibbles(), pass1Grids(work, job)); !st)
      return st;
    const std::span<const uint8_t> finished = (*reduced)[i];
    if (finished.size() != halo.points.size())
      return makeError(reducedHalos(work, job), "was written for another block layout");
    applyHalo(grid, halo, {finished.begin(), finished.end()});
    KeptHeights* store = keeps ? kept[w].get() : nullptr;
    if (store) {
      if (Status st = restoreKept(*store, origin, s.block, (*keptRecords)[i], keptPath); !st)
        return st;
    } else if (Status st =
                   readBlockWindow(context, windows, origin.x, origin.y, s.block, heights[w], w);
               !st) {
      return st;
    }
    ChunkMesher mesher(s.layout, s.budget, grid,
                       store ? static_cast<const HeightSampler&>(*store)
                             : static_cast<const HeightSampler&>(none));
    auto built = buildBlockChunks(context, blockNodes[k], keeps ? nullptr : &heights[w], mesher,
                                  grid, windows, w);
    if (!built) return built.error();
    BlockCoarse c;
    c.heights = std::move(built->points);
    const int32_t x1 = std::min(origin.x + s.block, s.layout.cellsX),
                  y1 = std::min(origin.y + s.block, s.layout.cellsY);
    for (int32_t y = origin.y; y <= origin.y + s.block; ++y)
      for (int32_t x = origin.x; x <= origin.x + s.block; ++x)
        if (const uint8_t a = grid.get(x, y); a >= coarse) {
          c.activations.emplace_back(ActivationGrid::key(x, y), a);
          // The heights a window would have given (buildBlockChunks' points), from the store.
          if (store && x <= x1 && y <= y1)
            c.heights.emplace_back(SparseHeights::key(x, y), float(store->at(x, y)));
        }
    if (store) store->dropBlock(origin);
    if (pyramid) {
      pyramid->add(blockNodes[k], std::move(built->tiles));
      spool.add(blockNodes[k], built->blockTexture);
    }
    chunks.put(i, packChunks(built->chunks, nodes));
    coarseRecords[i] = packBlockCoarse(c);
    progress.advance();
    return {};
  });
  progress.end();
  if (!done) return done;
  if (Status st = chunks.commit(blocks); !st) return st;
  if (Status st = writeBlockRecords(pass2Coarse(work, job), StageFile::kBlockCoarse, coarseRecords);
      !st)
    return st;
  uint64_t misses = 0;
  for (const auto& store : kept) misses += store->misses();
  if (misses > 0)
    return Error{"internal error: pass 2 read " + std::to_string(misses) +
                 " heights that pass 1 had not kept"};
  if (!pyramid) return {};
  if (Status st = spool.writeSorted(jobTextures(work, o, job)); !st) return st;
  return writeStageFile(jobTiles(work, o, job), StageFile::kJobTiles,
                        packFrontier(pyramid->takeFrontier()));
}

// Pass 2 from the heights (and textures) pass 1 kept: it reads no raster.
Status pass2FromKept(const std::string& work, int job, unsigned threads, StageContext& s,
                     Progress& progress) {
  if (!passOneKeeps(s.plan.options))
    return makeError(planPath(work),
                     "is a build whose pass 2 reads the DEM (run it with "
                     "`terralod build-stage pass2`)");
  std::vector<NodeRecord> nodes = std::move(s.nodes);
  NoWindows none;
  return pass2Blocks(work, job, std::max(1u, threads), s, nodes, nullptr, none, progress);
}

}  // namespace

Status pass2Stage(const std::string& work, int job, unsigned threads, Progress& progress) {
  auto stage = loadJobStage(work, job);
  if (!stage) return stage.error();
  if (passOneKeeps(stage->plan.options)) return pass2FromKept(work, job, threads, *stage, progress);
  const StageContext& s = *stage;
  const BuildOptions& o = s.plan.options;
  threads = std::max(1u, threads);
  std::vector<NodeRecord> nodes = std::move(stage->nodes);
  auto reader = openStageDem(s, work);
  if (!reader) return reader.error();
  auto image = openImage(o, s.info());
  if (!image) return image.error();
  TextureBuild textures;
  std::unique_ptr<TexturePass> texturePass;
  if (o.textures) {
    textures = textureBuildFor(o, s.layout, s.budget, s.plan.source, image->get());
    texturePass = std::make_unique<TexturePass>(s.layout, textures, nodes, threads);
    if (Status st = texturePass->open(); !st) return st;
  }
  DemWindows windows(**reader, threads, nullptr);
  return pass2Blocks(work, job, threads, s, nodes, texturePass.get(), windows, progress);
}

namespace {

// The textures of the nodes above the pass-2 jobs' frontiers, from the frontiers' tiles, one
// job's at a time: two of the top nodes built at once would hold twice the largest tiles
// (the coarse job's peak went from 482 to 673 MB at 16385² in 16 jobs, for 1.5 s).
Result<NodeTextures> topTextures(const std::string& work, const StageContext& s,
                                 const TexturePass& pass) {
  const int32_t blockLevel = blockLevelOf(s.layout, s.block);
  std::vector<std::vector<uint32_t>> frontiers;
  std::vector<uint32_t> all;
  for (int job = 0; job < s.plan.jobs; ++job) {
    const std::vector<uint32_t> blocks = jobBlockNodes(s, job);
    frontiers.push_back(TilePyramid::frontierOf(
        s.nodes, TilePyramid::buildableFrom(s.nodes, blockLevel, blocks), blocks));
    all.insert(all.end(), frontiers.back().begin(), frontiers.back().end());
  }
  TilePyramid pyramid(pass, s.nodes, TilePyramid::ancestorsOf(s.nodes, all));
  for (int job = 0; job < s.plan.jobs; ++job) {
    auto tiles = readFrontier(jobTiles(work, s.plan.options, job), frontiers[size_t(job)]);
    if (!tiles) return tiles.error();
    for (auto& [node, t] : *tiles) pyramid.add(node, std::move(t));
  }
  return pyramid.takeTextures();
}

// Writes coarse.chunks: the coarse chunks in their order, each with the texture this job
// made (`top`); a texture a pass-2 job made is left empty here, and assemble takes it from
// that job's file (JobTextures).
Status writeCoarseChunks(const std::string& work, const StageContext& s,
                         const std::vector<BuiltChunk>& chunks,
                         const std::vector<NodeRecord>& nodes, NodeTextures top, bool textured) {
  std::unordered_map<uint32_t, size_t> topOf;
  for (size_t i = 0; i < top.size(); ++i) topOf.emplace(top[i].first, i);
  const std::vector<int> madeBy =
      textured ? JobTextures::madeBy(s, nodes) : std::vector<int>(nodes.size(), -1);
  auto out = StageFileWriter::create(coarseChunks(work), StageFile::kChunks);
  if (!out) return out.error();
  Packer p;
  for (const BuiltChunk& c : chunks) {
    packChunkMesh(p, c, nodes);
    if (!textured) {
      p.putBytes(c.texture);
    } else if (auto t = topOf.find(c.node); t != topOf.end()) {
      p.putBytes(top[t->second].second);
    } else if (madeBy[c.node] >= 0) {
      p.putBytes({});
    } else {
      return Error{"internal error: chunk " + std::to_string(nodes[c.node].level) + "/" +
                   std::to_string(nodes[c.node].x) + "/" + std::to_string(nodes[c.node].y) +
                   " has no texture"};
    }
    if (Status st = out->write(p.bytes()); !st) return st;
    p.bytes().clear();
  }
  return out->commit();
}

}  // namespace

Status coarseStage(const std::string& work, unsigned threads, Progress& progress) {
  auto stage = loadStage(work);
  if (!stage) return stage.error();
  const StageContext& s = *stage;
  threads = std::max(1u, threads);
  const BuildOptions& o = s.plan.options;
  std::vector<NodeRecord> nodes = s.nodes;
  const int32_t blockLevel = blockLevelOf(s.layout, s.block);
  const std::vector<uint32_t> coarseNodes = coarseNodesOf(nodes, blockLevel);

  SparseHeights heights(s.layout, s.block);
  auto points = std::make_shared<ActivationGrid::SparsePoints>();
  auto reduced = readReduceSummary(work);
  if (!reduced) return reduced.error();
  for (const auto& [key, a] : reduced->activations) points->findOrAdd(key, a);
  progress.begin("coarse", s.plan.blocks.size() + coarseNodes.size());
  for (int job = 0; job < s.plan.jobs; ++job) {
    const auto range = s.plan.jobBlocks(job);
    const std::string halosPath = pass1Halos(work, job), coarsePath = pass2Coarse(work, job);
    auto halos = BlockRecords::read(halosPath, StageFile::kPass1Halos, range[1] - range[0]);
    if (!halos) return halos.error();
    auto coarse = BlockRecords::read(coarsePath, StageFile::kBlockCoarse, range[1] - range[0]);
    if (!coarse) return coarse.error();
    for (size_t i = 0; i < range[1] - range[0]; ++i) {
      auto h = unpackPass1Halo((*halos)[i], halosPath);
      if (!h) return h.error();
      recordLines(heights, h->lines);
      auto c = unpackBlockCoarse((*coarse)[i], coarsePath);
      if (!c) return c.error();
      heights.recordPoints(c->heights);
      for (const auto& [key, a] : c->activations) points->findOrAdd(key, a);
      progress.advance();
    }
  }
  const ActivationGrid grid = ActivationGrid::sparse(points);
  NodeTextures top;
  if (o.textures) {
    // The top of the pyramid is made of the jobs' tiles: no DEM, no image.
    const TextureBuild textureBuild =
        textureBuildFor(o, s.layout, s.budget, s.plan.source, nullptr);
    const TexturePass pass(s.layout, textureBuild, nodes, threads);
    auto made = topTextures(work, s, pass);
    if (!made) return made.error();
    top = std::move(made).value();
  }
  ChunkPassContext context{s.layout,          s.budget,           nodes,
                           s.block,           o.compressionLevel, nullptr,
                           MeshMethod::kRtin, chunkPayloadOf(o)};
  std::vector<std::unique_ptr<ChunkMesher>> meshers(threads);
  for (auto& m : meshers) m = std::make_unique<ChunkMesher>(s.layout, s.budget, grid, heights);
  auto built = buildCoarseChunks(context, coarseNodes, meshers, progress);
  progress.end();
  if (!built) return built.error();
  if (heights.misses() > 0)
    return Error{"internal error: " + std::to_string(heights.misses()) +
                 " heights were needed that the staged build had not kept"};
  return writeCoarseChunks(work, s, *built, nodes, std::move(top), o.textures);
}

Result<BuildSummary> assembleStage(const std::string& work, Progress& progress) {
  auto stage = loadStage(work);
  if (!stage) return stage.error();
  const StageContext& s = *stage;
  const BuildOptions& o = s.plan.options;
  const DemInfo& info = s.info();
  auto reduced = readReduceSummary(work);
  if (!reduced) return reduced.error();
  auto writer = TilesetWriter::create(o.output);
  if (!writer) return writer.error();
  std::vector<NodeRecord> nodes = s.nodes;
  progress.begin("assembling", size_t(s.plan.jobs) + 1);
  for (int job = 0; job < s.plan.jobs; ++job) {
    if (o.textures && passOneKeeps(o)) {
      // Pass 1 made this job's chunk textures; its chunk file holds none.
      auto in = StageFileReader::open(chunkTextures(work, job), StageFile::kChunkTextures);
      if (!in) return in.error();
      ChunkTexturesInStep textures(std::move(*in));
      if (Status st = appendChunksFrom(pass2Chunks(work, job), nodes, **writer, textures); !st)
        return st.error();
      if (Status st = textures.finish(); !st) return st.error();
    } else {
      OwnTextures own;
      if (Status st = appendChunksFrom(pass2Chunks(work, job), nodes, **writer, own); !st)
        return st.error();
    }
    progress.advance();
  }
  auto made = o.textures ? JobTextures::open(work, s) : Result<JobTextures>(JobTextures());
  if (!made) return made.error();
  if (Status st = appendChunksFrom(coarseChunks(work), nodes, **writer, *made); !st)
    return st.error();
  if (Status st = made->finish(); !st) return st.error();
  progress.end();
  for (const NodeRecord& n : nodes)
    if (n.blobBytes == 0)
      return makeError(work, "a chunk is missing from the stage files (" + std::to_string(n.level) +
                                 "/" + std::to_string(n.x) + "/" + std::to_string(n.y) + ")");
  BuildSummary summary;
  summary.sourceSamples = uint64_t(info.columns) * uint64_t(info.rows);
  summary.streamed = true;
  summary.textureRefine = s.plan.source.imageRefine;
  TextureBuild textures;
  if (o.textures) {
    textures = textureBuildFor(o, s.layout, s.budget, s.plan.source, nullptr);
    markInheritedTextures(textures.plan, nodes);
  }
  summarizeNodes(nodes, summary);
  summary.levels = s.layout.levelCount();
  const TilesetHeader header =
      staticHeader(info, o, s.layout, s.budget, reduced->zMin, reduced->zMax, 0);
  if (Status st = (*writer)->finish(
          header, nodes,
          tilesetMetadataJson(info, o, summary, s.layout, o.textures ? &textures : nullptr));
      !st)
    return st.error();
  std::error_code ec;
  summary.fileBytes = fs::file_size(o.output, ec);
  return summary;
}

Result<BuildSummary> buildInStages(const BuildOptions& options, const std::string& work, int jobs,
                                   Progress& progress, const Warn& warn) {
  const auto start = std::chrono::steady_clock::now();
  auto plan = planStage(options, work, jobs, progress, warn);
  if (!plan) {
    if (fs::is_directory(work) && holdsOnlyStageFiles(work)) cleanWorkDirectory(work);
    return plan.error();
  }
  auto failed = [&](const Error& e) -> Result<BuildSummary> {
    cleanWorkDirectory(work);
    return e;
  };
  const unsigned threads = options.threads ? options.threads : hardwareThreads();
  auto run = [&](BuildStage stage) -> Result<TaskEnd> {
    Result<TaskEnd> end = TaskEnd::kDone;
    for (int j = 0; j < (perJob(stage) ? plan->jobs : 1) && end && *end == TaskEnd::kDone; ++j)
      end = runStageTask(work, stage, j, threads, progress);
    if (end && *end == TaskEnd::kNotReady)
      return Result<TaskEnd>(Error{"internal error: a stage ran before the one it needs"});
    return end;
  };
  for (int attempt = 0; attempt < 2; ++attempt) {
    if (auto end = run(BuildStage::kPass1); !end) return failed(end.error());
    auto end = run(BuildStage::kReduce);
    if (!end) return failed(end.error());
    if (*end == TaskEnd::kDone) break;
  }
  for (BuildStage stage : {BuildStage::kPass2, BuildStage::kCoarse})
    if (auto end = run(stage); !end) return failed(end.error());
  auto summary = assembleStage(work, progress);
  if (!summary) return failed(summary.error());
  cleanWorkDirectory(work);
  summary->totalSeconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return summary;
}

namespace {

// Whether every task of the stage before `stage` has recorded that it finished.
Result<bool> stageBeforeFinished(const std::string& work, BuildStage stage) {
  if (stage == BuildStage::kPass1) return true;
  auto plan = readPlan(work);
  if (!plan) return plan.error();
  const BuildStage before = kJobStages[size_t(stage) - 1];
  for (int t = 0; t < (perJob(before) ? plan->jobs : 1); ++t)
    if (!fs::exists(taskStatusPath(work, before, t, "ok"))) return false;
  return true;
}

}  // namespace

const char* stageName(BuildStage stage) {
  switch (stage) {
    case BuildStage::kPass1:
      return "pass1";
    case BuildStage::kReduce:
      return "reduce";
    case BuildStage::kPass2:
      return "pass2";
    case BuildStage::kCoarse:
      return "coarse";
    case BuildStage::kAssemble:
      break;
  }
  return "assemble";
}

std::optional<BuildStage> parseStageName(const std::string& name) {
  for (BuildStage s : kJobStages)
    if (name == stageName(s)) return s;
  return std::nullopt;
}

std::string taskStatusPath(const std::string& work, BuildStage stage, int task,
                           const std::string& ending) {
  return work + "/status/" + stageName(stage) + "-" + std::to_string(task) + "." + ending;
}

bool stageReadsRasters(const BuildOptions& options, BuildStage stage) {
  return stage == BuildStage::kPass1 || (stage == BuildStage::kPass2 && !passOneKeeps(options));
}

std::vector<std::string> stageProgram(const BuildOptions& options, BuildStage stage,
                                      const std::string& terralod,
                                      const std::string& terralodStage) {
  if (terralodStage.empty() || stageReadsRasters(options, stage)) return {terralod, "build-stage"};
  return {terralodStage};
}

namespace {

Result<TaskEnd> endOf(const Status& status) {
  if (!status) return status.error();
  return TaskEnd::kDone;
}

// A task of a stage that reads no raster (stageReadsRasters false).
Result<TaskEnd> rasterFreeTask(const std::string& work, BuildStage stage, int task,
                               unsigned threads, Progress& progress) {
  switch (stage) {
    case BuildStage::kReduce: {
      auto reduced = reduceStage(work, progress);
      if (!reduced) return reduced.error();
      return *reduced == ReduceResult::kReplanned ? TaskEnd::kReplanned : TaskEnd::kDone;
    }
    case BuildStage::kPass2: {
      auto s = loadJobStage(work, task);
      if (!s) return s.error();
      return endOf(pass2FromKept(work, task, threads, *s, progress));
    }
    case BuildStage::kCoarse:
      return endOf(coarseStage(work, threads, progress));
    case BuildStage::kAssemble: {
      auto summary = assembleStage(work, progress);
      if (!summary) return summary.error();
      return TaskEnd::kDone;
    }
    case BuildStage::kPass1:
      break;
  }
  return makeError(planPath(work),
                   "pass1 reads the DEM (run it with `terralod build-stage pass1`)");
}

// Runs `body` as task `task` of `stage` once the stage before has finished, and records how it
// ended (WORK/status) with what it cost.
Result<TaskEnd> recordTask(const std::string& work, BuildStage stage, int task,
                           const std::function<Result<TaskEnd>()>& body) {
  std::error_code ec;
  for (const char* ending : {"ok", "err", "replan"})
    fs::remove(taskStatusPath(work, stage, task, ending), ec);
  const auto start = std::chrono::steady_clock::now();
  if (auto ready = stageBeforeFinished(work, stage); !ready || !*ready)
    return ready ? Result<TaskEnd>(TaskEnd::kNotReady) : Result<TaskEnd>(ready.error());
  Result<TaskEnd> end =
      !perJob(stage) && task != 0
          ? makeError(planPath(work), std::string("stage ") + stageName(stage) + " has one task, 0")
          : body();
  const std::string ending = !end ? "err" : *end == TaskEnd::kReplanned ? "replan" : "ok";
  // The error line, or what the task cost (for the driver's figures).
  std::string text;
  if (!end) {
    text = end.error().message + "\n";
  } else {
    rusage usage{};
    ::getrusage(RUSAGE_SELF, &usage);
    char figures[96];
    std::snprintf(figures, sizeof figures, "seconds %.3f peak_rss_mb %.1f\n",
                  std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(),
                  double(usage.ru_maxrss) / 1024.0);
    text = figures;
  }
  if (Status st = writeText(taskStatusPath(work, stage, task, ending), text); !st && end)
    return st.error();
  return end;
}

}  // namespace

Result<TaskEnd> runStageTask(const std::string& work, BuildStage stage, int task, unsigned threads,
                             Progress& progress) {
  return recordTask(work, stage, task, [&]() -> Result<TaskEnd> {
    if (stage == BuildStage::kPass1) return endOf(pass1Stage(work, task, threads, progress));
    if (stage == BuildStage::kPass2) return endOf(pass2Stage(work, task, threads, progress));
    return rasterFreeTask(work, stage, task, threads, progress);
  });
}

Result<TaskEnd> runRasterFreeStageTask(const std::string& work, BuildStage stage, int task,
                                       unsigned threads, Progress& progress) {
  return recordTask(work, stage, task,
                    [&] { return rasterFreeTask(work, stage, task, threads, progress); });
}

void cleanWorkDirectory(const std::string& work, KeepLogs logs) {
  std::error_code ec;
  for (const char* d : kStageDirs) fs::remove_all(work + "/" + d, ec);
  fs::remove(coarseChunks(work), ec);
  fs::remove(planPath(work), ec);
  if (logs == KeepLogs::kNo ||
      (fs::is_directory(work + "/logs", ec) && fs::is_empty(work + "/logs", ec)))
    fs::remove_all(work + "/logs", ec);
  if (fs::is_directory(work, ec) && fs::is_empty(work, ec)) fs::remove(work, ec);
}

}  // namespace terralod
