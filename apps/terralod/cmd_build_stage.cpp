// terralod build-stage STAGE WORK [--task T]: one task of a staged build, as a job runs it.

#include "commands.h"
#include "stage_task.h"
#include "terralod/raster/dem_reader.h"

namespace terralod::cli {

void addBuildStageCommand(CLI::App& root, Runner& run) {
  auto* cmd = root.add_subcommand(
      "build-stage",
      "Run one task of a staged build (what `build --scheduler` submits as jobs; see `build "
      "--scheduler none` for the order). `terralod-stage` runs the tasks that read no raster "
      "without loading GDAL");
  auto args = std::make_shared<StageTaskArgs>();
  addStageTaskOptions(*cmd, *args);
  cmd->callback([&run, args] {
    run = [args] {
      // A job reads its blocks' windows one at a time, in order: GDAL's cache need hold only
      // a few rows of the raster's tiles. (64 MB, the default elsewhere, was an eighth of a
      // pass-2 job's peak at 16385², and no faster: with 16 MB the job took 0.96x the wall.)
      setGdalCacheBytes(uint64_t{16} << 20);
      return runStageTaskCommand(*args, "terralod", runStageTask);
    };
  });
}

}  // namespace terralod::cli
