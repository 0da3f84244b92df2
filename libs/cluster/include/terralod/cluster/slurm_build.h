#pragma once
// `terralod build --scheduler slurm`: a staged build (terralod/build/build_stages.h) run as
// Slurm array jobs. The plan is written here; then pass 1, reduce, pass 2, coarse and assemble
// are submitted at once, each stage's job depending (afterok) on every task of the stage
// before. The driver follows the tasks through squeue and the status files the stage commands
// write, with a progress bar:
//  - a task that leaves the queue without recording its end (killed, cancelled, out of memory,
//    node failure) is submitted again, at most `retries` times, and the next stage's job is
//    made to depend on the new task instead (scontrol update);
//  - a task that records an error (bad data, a full disk) ends the build with that error line:
//    the other jobs are cancelled, the work directory emptied, and no tileset is written;
//  - a reduce that finds the height range estimate wrong (status 3) gets pass 1 onwards
//    submitted again with the corrected plan.
// The tileset appears (atomically, from the assemble job) only when every stage succeeded.

#include <string>
#include <vector>

#include "terralod/build/build_stages.h"
#include "terralod/build/builder.h"
#include "terralod/core/progress.h"
#include "terralod/core/result.h"

namespace terralod {

struct SlurmBuildOptions {
  std::string work;                     ///< shared by every node
  int jobs = 0;                         ///< block jobs of pass 1 and 2 (0: automatic)
  std::vector<std::string> sbatchArgs;  ///< added to every sbatch
  int retries = 2;                      ///< resubmissions of one lost task
  std::string executable;               ///< the terralod the jobs run (absolute, shared)
  /// terralod-stage, which the tasks that read no raster run instead (stageReadsRasters):
  /// it starts without loading GDAL. Empty: `executable build-stage` runs every task.
  std::string stageExecutable;
  double pollSeconds = 0.5;
};

/// What one stage's tasks cost, as each task measured itself (wall from start to its end,
/// its process's peak resident memory).
struct StageFigures {
  BuildStage stage = BuildStage::kPass1;
  int tasks = 0;
  double maxSeconds = 0, totalSeconds = 0, maxRssMB = 0;
};

struct SlurmBuildResult {
  BuildSummary summary;
  std::vector<StageFigures> stages;  ///< in stage order
};

Result<SlurmBuildResult> buildOnSlurm(const BuildOptions& options, const SlurmBuildOptions& slurm,
                                      Progress& progress, const Warn& warn);

}  // namespace terralod
