#pragma once
// `terralod build --scheduler local|slurm|none --work-dir W`: the build as stages over W
// (libs/build build_stages.h), run here, submitted to Slurm, or planned for another scheduler.

#include <string>

#include "terralod/build/builder.h"
#include "terralod/core/progress.h"
#include "terralod/core/result.h"

namespace terralod::cli {

struct StagedRequest {
  std::string scheduler;  ///< empty: not staged
  std::string work;
  int jobs = 0;  ///< 0: automatic
  std::string sbatchArgs;
  int retries = 2;
};

/// kFigures: print what each stage's tasks cost (Slurm; `build --verbose`).
enum class StageReport { kQuiet, kFigures };
Result<BuildSummary> buildStaged(const BuildOptions& options, const StagedRequest& request,
                                 Progress& progress, StageReport report);

/// Writes the plan and prints the stage commands; returns the exit status.
int planForOtherScheduler(const BuildOptions& options, const StagedRequest& request);

/// This executable's absolute path (what jobs run).
std::string selfExecutable();

}  // namespace terralod::cli
