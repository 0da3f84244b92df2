#pragma once
// What the stages of a staged build (build_stages.h) share: where each stage's files are in the
// work directory, and what every stage derives from the plan (StageContext). Internal to
// libs/build; the record layouts the stages hand each other are in stage_records.h.

#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "terralod/build/build_plan.h"
#include "terralod/build/builder.h"
#include "terralod/build/error_budget.h"
#include "terralod/build/height_source.h"
#include "terralod/build/tree_layout.h"
#include "terralod/core/bintree.h"
#include "terralod/core/progress.h"
#include "terralod/core/result.h"
#include "terralod/format/tileset_format.h"
#include "terralod/raster/dem_reader.h"
#include "terralod/raster/image_drape.h"

namespace terralod::stages {

// WORK/plan.json; per job J: pass1/job-J.halo, pass1/job-J.grid, (RTIN) pass1/job-J.kept,
// reduce/job-J.halo, pass2/job-J.chunks, pass2/job-J.coarse and, textured,
// STAGE/job-J.textures, STAGE/job-J.tiles (STAGE: the pass that makes textures) and (RTIN)
// pass1/job-J.chunk-textures; once: reduce/coarse.points, coarse.chunks;
// status/STAGE-TASK.ENDING.
std::string planPath(const std::string& work);
std::string pass1Halos(const std::string& work, int job);
std::string pass1Grids(const std::string& work, int job);
std::string reducedHalos(const std::string& work, int job);
std::string pass2Chunks(const std::string& work, int job);
std::string pass2Coarse(const std::string& work, int job);

// Whether pass 1 keeps the heights pass 2 reads and makes the textures from the windows it
// reads, so that pass 2 reads no DEM: RTIN chunk meshes read only what KeptHeights keeps;
// greedy ones scan every sample of their block, so their pass 2 reads it again (and makes the
// textures from it).
bool passOneKeeps(const BuildOptions& o);
std::string jobTextures(const std::string& work, const BuildOptions& o, int job);
std::string jobTiles(const std::string& work, const BuildOptions& o, int job);
std::string keptHeights(const std::string& work, int job);
std::string chunkTextures(const std::string& work, int job);
std::string coarsePoints(const std::string& work);
std::string coarseChunks(const std::string& work);

inline constexpr const char* kStageDirs[] = {"pass1", "reduce", "pass2", "status"};

/// The stage directories under `work`.
Status makeDirectories(const std::string& work);

// Whether everything in WORK is what the stages write (so it may be cleared).
bool holdsOnlyStageFiles(const std::string& work);

/// Writes a small text file atomically.
Status writeText(const std::string& path, const std::string& text);

// What every stage derives from the plan (without opening the DEM: openStageDem).
struct StageContext {
  BuildPlan plan;
  TreeLayout layout;
  ErrorBudget budget;
  int32_t block = 0;
  int32_t blocksX = 0;
  std::vector<NodeRecord> nodes;     ///< the tree (enumerateNodes), statistics not filled in
  std::vector<uint32_t> blockNodes;  ///< plan.blocks' nodes, in the same order
  GridPoint origin(size_t k) const {
    return {plan.blocks[k][0] * block, plan.blocks[k][1] * block};
  }
  size_t gridBlock(size_t k) const {
    return size_t(plan.blocks[k][1]) * size_t(blocksX) + size_t(plan.blocks[k][0]);
  }
  const DemInfo& info() const { return plan.source.info; }
};

Result<BuildPlan> readPlan(const std::string& work);
/// The plan and the tree; an error if the plan's blocks are not its raster's.
Result<StageContext> loadStage(const std::string& work);
/// The DEM, for a stage that reads it; an error if it is not the raster the plan was made for.
Result<std::unique_ptr<DemReader>> openStageDem(const StageContext& s, const std::string& work);

// The block nodes job `job` works on.
std::vector<uint32_t> jobBlockNodes(const StageContext& s, int job);

/// An error naming the plan unless `job` is one of its jobs.
Status checkJob(const StageContext& s, int job, const std::string& work);

// Runs fn(k, worker) for the blocks of a job, stopping at the first error.
Status forBlocks(std::array<size_t, 2> range, unsigned threads,
                 const std::function<Status(size_t, unsigned)>& fn);

/// The image draped as colour (`--texture-image`), or null.
Result<std::unique_ptr<ImageDrape>> openImage(const BuildOptions& o, const DemInfo& info);

// Heights nobody reads: chunk meshers get their block's window before they build.
class NoHeights final : public HeightSampler {
 public:
  double at(int32_t, int32_t) const override { return std::nan(""); }
};

// Windows nobody reads: a pass 2 from the heights pass 1 kept, which makes no textures.
class NoWindows final : public HeightWindows {
 public:
  Status read(int32_t, int32_t, int32_t, int32_t, float*, unsigned) override {
    return Error{"internal error: a stage without the DEM was asked for its heights"};
  }
};

/// An error unless `work` is new, empty or a staged build's own.
Status checkWorkDirectory(const std::string& work);

/// The error for a DEM with voids.
extern const char* const kVoidsRefused;

// The data's height range, read in strips of about 16 MB (what a local build that reads the
// raster whole makes its budget from).
Result<std::array<double, 2>> exactHeightRange(const DemReader& reader, Progress& progress);

/// A local path made absolute (jobs may run elsewhere); URLs and /vsi paths as they are.
std::string absolute(const std::string& path);

}  // namespace terralod::stages
