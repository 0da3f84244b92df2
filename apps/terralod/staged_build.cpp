#include "staged_build.h"

#include <unistd.h>

#include <cstdio>
#include <filesystem>

#include "commands.h"
#include "terralod/build/build_stages.h"
#include "terralod/cluster/slurm.h"
#include "terralod/cluster/slurm_build.h"

namespace terralod::cli {

std::string selfExecutable() {
  std::error_code ec;
  const auto path = std::filesystem::read_symlink("/proc/self/exe", ec);
  return ec ? std::string("terralod") : path.string();
}

// terralod-stage beside this terralod, or empty.
std::string stageExecutable() {
  const std::filesystem::path self = selfExecutable();
  if (!self.is_absolute()) return {};
  const std::filesystem::path stage = self.parent_path() / "terralod-stage";
  return ::access(stage.c_str(), X_OK) == 0 ? stage.string() : std::string();
}

Result<BuildSummary> buildStaged(const BuildOptions& options, const StagedRequest& request,
                                 Progress& progress, StageReport report) {
  if (request.scheduler == "local")
    return buildInStages(options, request.work, request.jobs, progress, warn);
  SlurmBuildOptions slurm;
  slurm.work = request.work;
  slurm.jobs = request.jobs;
  slurm.sbatchArgs = splitArguments(request.sbatchArgs);
  slurm.retries = request.retries;
  slurm.executable = selfExecutable();
  slurm.stageExecutable = stageExecutable();
  auto built = buildOnSlurm(options, slurm, progress, warn);
  if (!built) return built.error();
  if (report == StageReport::kFigures)
    for (const StageFigures& f : built->stages)
      std::printf("terralod: %-8s %3d task(s): %.2f s longest, %.2f s in all, peak RSS %.1f MB\n",
                  stageName(f.stage), f.tasks, f.maxSeconds, f.totalSeconds, f.maxRssMB);
  return built->summary;
}

int planForOtherScheduler(const BuildOptions& options, const StagedRequest& request) {
  NullProgress quiet;
  auto plan = planStage(options, request.work, request.jobs, quiet, warn);
  if (!plan) return fail(plan.error().message);
  const std::string self = selfExecutable();
  const std::string stageTool = stageExecutable();
  const std::string work = std::filesystem::absolute(request.work).string();
  std::printf(
      "terralod: wrote %s/plan.json: %zu blocks in %d jobs. Run these stages in order, each "
      "once every task of the one before has exited with status 0:\n",
      work.c_str(), plan->blocks.size(), plan->jobs);
  for (BuildStage stage : kJobStages) {
    // The stages that read no raster start faster without GDAL, in terralod-stage.
    std::string program;
    for (const std::string& word : stageProgram(plan->options, stage, self, stageTool))
      program += (program.empty() ? "" : " ") + word;
    if (perJob(stage))
      std::printf("  %s %s %s --task T    for T = 0 .. %d (in parallel)\n", program.c_str(),
                  stageName(stage), work.c_str(), plan->jobs - 1);
    else
      std::printf("  %s %s %s\n", program.c_str(), stageName(stage), work.c_str());
  }
  std::printf(
      "Exit status 3 from reduce: the height range estimate was wrong and the plan is updated; "
      "run pass1 and reduce again. Each task records how it ended in %s/status.\n",
      work.c_str());
  return 0;
}

}  // namespace terralod::cli
