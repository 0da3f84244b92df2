#pragma once
// A static build as explicit stages over a shared work directory, so that a batch scheduler can
// run it as jobs on many machines (docs/architecture.md, "Staged builds"). Each stage reads the
// plan and the files of the stages before it and writes its own; no job holds the whole
// activation grid or the whole raster. The result is byte for byte the local build's.
//
//   plan        (once)      WORK/plan.json
//   pass1 J     (per job)   WORK/pass1/job-J.halo, job-J.grid     (a record per block of J)
//   reduce      (once)      WORK/reduce/job-J.halo, coarse.points (or a new plan: see below)
//   pass2 J     (per job)   WORK/pass2/job-J.chunks, job-J.coarse (+ .textures, .tiles)
//   coarse      (once)      WORK/coarse.chunks
//   assemble    (once)      OUT.tlod (atomically)
//
// When the plan's height range is an estimate (a raster too large to read whole first) and the
// data leave it, the reduce writes a new plan with the true range and asks for pass 1 again
// (ReduceResult::kReplanned), as a local streamed build makes a second attempt.

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "terralod/build/build_plan.h"
#include "terralod/build/builder.h"
#include "terralod/core/progress.h"
#include "terralod/core/result.h"

namespace terralod {

using Warn = std::function<void(const std::string&)>;

/// Checks the request as a local build would (input, options, output directory, draped
/// image), prepares WORK (creating it; a previous build's files in it are removed; a directory
/// holding anything else is refused) and writes the plan for `jobs` block jobs (0: one per
/// block, at most 64).
Result<BuildPlan> planStage(const BuildOptions& options, const std::string& work, int jobs,
                            Progress& progress, const Warn& warn);

Status pass1Stage(const std::string& work, int job, unsigned threads, Progress& progress);

enum class ReduceResult { kDone, kReplanned };
Result<ReduceResult> reduceStage(const std::string& work, Progress& progress);

Status pass2Stage(const std::string& work, int job, unsigned threads, Progress& progress);

Status coarseStage(const std::string& work, unsigned threads, Progress& progress);

/// Writes the tileset named in the plan.
Result<BuildSummary> assembleStage(const std::string& work, Progress& progress);

/// Every stage in this process, one after the other (what a scheduler runs as jobs).
Result<BuildSummary> buildInStages(const BuildOptions& options, const std::string& work, int jobs,
                                   Progress& progress, const Warn& warn);

/// The stages a scheduler runs as jobs (after the plan, which the submitting command writes).
enum class BuildStage { kPass1, kReduce, kPass2, kCoarse, kAssemble };
inline constexpr BuildStage kJobStages[] = {BuildStage::kPass1, BuildStage::kReduce,
                                            BuildStage::kPass2, BuildStage::kCoarse,
                                            BuildStage::kAssemble};
const char* stageName(BuildStage stage);
std::optional<BuildStage> parseStageName(const std::string& name);
/// Whether the stage has one task per block job (else one task).
inline bool perJob(BuildStage stage) {
  return stage == BuildStage::kPass1 || stage == BuildStage::kPass2;
}

/// How a stage task ended, recorded in WORK/status/STAGE-TASK.ok, .replan or .err (the error
/// line) for whatever follows the jobs.
/// kNotReady: the stage before has not finished (a scheduler started the task early, e.g. after
/// a job it depended on was cancelled while it waited); nothing is recorded, so a driver sees
/// the task lost and submits it again.
enum class TaskEnd { kDone, kReplanned, kNotReady };
std::string taskStatusPath(const std::string& work, BuildStage stage, int task,
                           const std::string& ending);
/// Runs task `task` of a stage (a job index for pass 1 and 2, 0 otherwise) and records its end.
Result<TaskEnd> runStageTask(const std::string& work, BuildStage stage, int task, unsigned threads,
                             Progress& progress);

/// Whether a stage's tasks read the DEM or the draped image: pass 1 always, pass 2 unless pass 1
/// kept the heights and made the textures (an RTIN build, the default), no other stage.
bool stageReadsRasters(const BuildOptions& options, BuildStage stage);
/// The command (before the stage's name) that runs a stage's tasks: `terralod build-stage`, or
/// `terralodStage` (terralod-stage; empty when there is none) for a stage that reads no raster.
std::vector<std::string> stageProgram(const BuildOptions& options, BuildStage stage,
                                      const std::string& terralod,
                                      const std::string& terralodStage);
/// runStageTask for a stage that reads no raster, as a program without raster readers runs it
/// (`terralod-stage`: it does not load GDAL, whose libraries take most of a short task's start).
/// A stage that reads one ends in an error naming the command that runs it. Nothing this calls
/// reaches GDAL: the program's link checks that.
Result<TaskEnd> runRasterFreeStageTask(const std::string& work, BuildStage stage, int task,
                                       unsigned threads, Progress& progress);

/// Removes what the stages wrote (and WORK itself when that leaves it empty); the jobs' logs
/// (WORK/logs) too unless asked to keep them (after a failure).
enum class KeepLogs { kNo, kYes };
void cleanWorkDirectory(const std::string& work, KeepLogs logs = KeepLogs::kNo);

}  // namespace terralod
