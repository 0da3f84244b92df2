// terralod-stage STAGE WORK [--task T]: a task of a staged build that reads no raster (reduce,
// coarse, assemble, and pass 2 of a build whose pass 1 kept the heights), as `terralod
// build-stage` runs it, in a program that does not link GDAL. A short task spends most of its
// start loading GDAL and its hundred libraries in `terralod` (docs/benchmarks.md, "Builds on a
// cluster"); the driver of `build --scheduler slurm` runs these tasks with this program when it
// sits beside `terralod`.

#include <cstdio>
#include <exception>
#include <new>

#include "stage_task.h"

int main(int argc, char** argv) {
  using namespace terralod::cli;
  CLI::App app{
      "terralod-stage: one task of a staged build that reads no raster (see `terralod "
      "build-stage`)."};
  app.failure_message([](const CLI::App*, const CLI::Error& e) {
    return std::string("terralod-stage: error: ") + e.what() + " (see --help)\n";
  });
  StageTaskArgs args;
  addStageTaskOptions(app, args);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 1;
  }
  try {
    return runStageTaskCommand(args, "terralod-stage", terralod::runRasterFreeStageTask);
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr, "terralod-stage: error: out of memory\n");
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "terralod-stage: error: internal error: %s\n", e.what());
    return 1;
  }
}
