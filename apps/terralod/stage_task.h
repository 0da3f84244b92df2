#pragma once
// One task of a staged build as a command runs it: what `terralod build-stage` and the
// GDAL-free `terralod-stage` share (their arguments, the threads a task takes, the exit status).

#include <string>

#include <CLI/CLI.hpp>

#include "terralod/build/build_stages.h"

namespace terralod::cli {

struct StageTaskArgs {
  std::string stage;  ///< pass1, reduce, pass2, coarse or assemble
  std::string work;
  int task = 0;
  unsigned threads = 0;  ///< 0: the CPUs Slurm allocated, else all cores
};

void addStageTaskOptions(CLI::App& app, StageTaskArgs& args);

/// runStageTask, or runRasterFreeStageTask in a program without raster readers.
using StageTaskRunner = Result<TaskEnd> (*)(const std::string& work, BuildStage stage, int task,
                                            unsigned threads, Progress& progress);

/// Runs the task; prints one error line prefixed by `program` when it fails. The exit status:
/// 0 done, 1 failed, 3 replanned, 4 the stage before has not finished.
int runStageTaskCommand(const StageTaskArgs& args, const char* program, StageTaskRunner run);

}  // namespace terralod::cli
