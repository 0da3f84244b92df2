#include "stage_work.h"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <limits>
#include <mutex>
#include <optional>
#include <sstream>

#include "terralod/build/chunk_pass.h"
#include "terralod/core/atomic_file.h"
#include "terralod/core/parallel.h"

namespace terralod::stages {

namespace fs = std::filesystem;

namespace {

std::string jobFile(const std::string& work, const char* stage, int job, const char* ext) {
  return work + "/" + stage + "/job-" + std::to_string(job) + "." + ext;
}

// The pass that makes a textured build's textures (passOneKeeps).
const char* texturesDir(const BuildOptions& o) {
  return passOneKeeps(o) ? "pass1" : "pass2";
}

}  // namespace

// WORK/plan.json; per job J: pass1/job-J.halo, pass1/job-J.grid, (RTIN) pass1/job-J.kept,
// reduce/job-J.halo, pass2/job-J.chunks, pass2/job-J.coarse and, textured,
// STAGE/job-J.textures, STAGE/job-J.tiles (STAGE: the pass that makes textures) and (RTIN)
// pass1/job-J.chunk-textures; once: reduce/coarse.points, coarse.chunks;
// status/STAGE-TASK.ENDING.
std::string planPath(const std::string& work) {
  return work + "/plan.json";
}

std::string pass1Halos(const std::string& work, int job) {
  return jobFile(work, "pass1", job, "halo");
}

std::string pass1Grids(const std::string& work, int job) {
  return jobFile(work, "pass1", job, "grid");
}

std::string reducedHalos(const std::string& work, int job) {
  return jobFile(work, "reduce", job, "halo");
}

std::string pass2Chunks(const std::string& work, int job) {
  return jobFile(work, "pass2", job, "chunks");
}

std::string pass2Coarse(const std::string& work, int job) {
  return jobFile(work, "pass2", job, "coarse");
}

// Whether pass 1 keeps the heights pass 2 reads and makes the textures from the windows it
// reads, so that pass 2 reads no DEM: RTIN chunk meshes read only what KeptHeights keeps;
// greedy ones scan every sample of their block, so their pass 2 reads it again (and makes the
// textures from it).
bool passOneKeeps(const BuildOptions& o) {
  return o.mesher == MeshMethod::kRtin;
}

std::string jobTextures(const std::string& work, const BuildOptions& o, int job) {
  return jobFile(work, texturesDir(o), job, "textures");
}

std::string jobTiles(const std::string& work, const BuildOptions& o, int job) {
  return jobFile(work, texturesDir(o), job, "tiles");
}

std::string keptHeights(const std::string& work, int job) {
  return jobFile(work, "pass1", job, "kept");
}

std::string chunkTextures(const std::string& work, int job) {
  return jobFile(work, "pass1", job, "chunk-textures");
}

std::string coarsePoints(const std::string& work) {
  return work + "/reduce/coarse.points";
}

std::string coarseChunks(const std::string& work) {
  return work + "/coarse.chunks";
}

Status makeDirectories(const std::string& work) {
  for (const char* d : kStageDirs) {
    std::error_code ec;
    fs::create_directories(work + "/" + d, ec);
    if (ec) return makeError(work + "/" + d, "cannot create: " + ec.message());
  }
  return {};
}

// Whether everything in WORK is what the stages write (so it may be cleared).
bool holdsOnlyStageFiles(const std::string& work) {
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(work, ec)) {
    const std::string name = entry.path().filename().string();
    if (name != "plan.json" && name != "coarse.chunks" && name != "logs" &&
        std::find(std::begin(kStageDirs), std::end(kStageDirs), name) == std::end(kStageDirs))
      return false;
  }
  return !ec;
}

Status writeText(const std::string& path, const std::string& text) {
  auto file = AtomicFile::create(path);
  if (!file) return file.error();
  if (Status s = file->write(text); !s) return s;
  return file->commit();
}

Result<BuildPlan> readPlan(const std::string& work) {
  std::ifstream in(planPath(work));
  if (!in) return makeError(planPath(work), "missing (run the plan stage first)");
  std::stringstream text;
  text << in.rdbuf();
  return parseBuildPlan(text.str(), planPath(work));
}

Result<StageContext> loadStage(const std::string& work) {
  StageContext s;
  auto plan = readPlan(work);
  if (!plan) return plan.error();
  s.plan = std::move(plan).value();
  const BuildOptions& o = s.plan.options;
  const DemInfo& info = s.info();
  auto layout = makeTreeLayout(info.columns, info.rows, o.chunkCells);
  if (!layout) return layout.error();
  s.layout = *layout;
  s.block = s.plan.blockCells;
  s.blocksX = s.layout.gridX() / s.block;
  auto budget = makeErrorBudget(s.layout, o.maxError, s.plan.heightHi - s.plan.heightLo);
  if (!budget) return makeError(info.path, budget.error().message);
  s.budget = std::move(budget).value();
  // The blocks must be this raster's: a plan made for another would build nonsense.
  s.nodes = enumerateNodes(s.layout);
  s.blockNodes = blockNodesOf(s.nodes, blockLevelOf(s.layout, s.block));
  const std::vector<NodeRecord>& nodes = s.nodes;
  const std::vector<uint32_t>& blockNodes = s.blockNodes;
  bool same = blockNodes.size() == s.plan.blocks.size();
  for (size_t k = 0; same && k < blockNodes.size(); ++k)
    same = int32_t(nodes[blockNodes[k]].x) == s.plan.blocks[k][0] &&
           int32_t(nodes[blockNodes[k]].y) == s.plan.blocks[k][1];
  if (!same)
    return makeError(planPath(work), "was made for another raster or block size than " + o.input);
  return s;
}

Result<std::unique_ptr<DemReader>> openStageDem(const StageContext& s, const std::string& work) {
  const BuildOptions& o = s.plan.options;
  auto reader = DemReader::open(o.input, o.dem);
  if (!reader) return reader.error();
  const DemInfo& now = (*reader)->info();
  const DemInfo& planned = s.info();
  if (now.columns != planned.columns || now.rows != planned.rows ||
      now.spacingX != planned.spacingX || now.spacingY != planned.spacingY)
    return makeError(planPath(work), "was made for another raster than " + o.input +
                                         " (it has changed since the plan)");
  return reader;
}

// The block nodes job `job` works on.
std::vector<uint32_t> jobBlockNodes(const StageContext& s, int job) {
  const auto range = s.plan.jobBlocks(job);
  return {s.blockNodes.begin() + ptrdiff_t(range[0]), s.blockNodes.begin() + ptrdiff_t(range[1])};
}

Status checkJob(const StageContext& s, int job, const std::string& work) {
  if (job < 0 || job >= s.plan.jobs)
    return makeError(planPath(work), "has jobs 0.." + std::to_string(s.plan.jobs - 1) + ", not " +
                                         std::to_string(job));
  return {};
}

// Runs fn(k, worker) for the blocks of a job, stopping at the first error.
Status forBlocks(std::array<size_t, 2> range, unsigned threads,
                 const std::function<Status(size_t, unsigned)>& fn) {
  std::mutex mutex;
  std::optional<Error> failure;
  std::atomic<bool> failed{false};
  parallelFor(range[1] - range[0], threads, [&](size_t i, unsigned worker) {
    if (failed) return;
    if (Status s = fn(range[0] + i, worker); !s) {
      std::lock_guard lock(mutex);
      if (!failure) failure = s.error();
      failed = true;
    }
  });
  if (failure) return *failure;
  return {};
}

Result<std::unique_ptr<ImageDrape>> openImage(const BuildOptions& o, const DemInfo& info) {
  if (!o.textures || o.textureImage.empty()) return std::unique_ptr<ImageDrape>();
  return ImageDrape::open(o.textureImage, info);
}

Status checkWorkDirectory(const std::string& work) {
  if (fs::exists(work) && !fs::is_directory(work))
    return makeError(work, "is not a directory (the work directory of a staged build)");
  if (fs::is_directory(work) && !holdsOnlyStageFiles(work))
    return makeError(work,
                     "holds files other than a staged build's: give an empty or new directory");
  return {};
}

const char* const kVoidsRefused =
    "has voids; a staged build needs them filled first (e.g. with gdal_fillnodata), or build "
    "it on one machine";

// The data's height range, read in strips of about 16 MB (what a local build that reads the
// raster whole makes its budget from).
Result<std::array<double, 2>> exactHeightRange(const DemReader& reader, Progress& progress) {
  const DemInfo& info = reader.info();
  const int32_t strip = std::max(1, int32_t((uint64_t{16} << 20) / (uint64_t(info.columns) * 4)));
  std::vector<float> rows;
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  progress.begin("range", size_t((info.rows + strip - 1) / strip));
  for (int32_t y = 0; y < info.rows; y += strip) {
    const int32_t h = std::min(strip, info.rows - y);
    rows.resize(size_t(h) * info.columns);
    if (Status s = reader.readWindow(0, y, info.columns, h, rows.data()); !s) return s.error();
    for (float v : rows) {
      if (std::isnan(v)) return makeError(info.path, kVoidsRefused);
      lo = std::min(lo, double(v));
      hi = std::max(hi, double(v));
    }
    progress.advance();
  }
  progress.end();
  return std::array<double, 2>{lo, hi};
}

std::string absolute(const std::string& path) {
  if (path.empty() || path.find("://") != std::string::npos || path.rfind("/vsi", 0) == 0)
    return path;
  return fs::absolute(path).lexically_normal().string();
}

}  // namespace terralod::stages
