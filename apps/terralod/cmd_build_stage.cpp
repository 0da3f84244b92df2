// terralod build-stage STAGE WORK [--task T]: one task of a staged build, as a job runs it.

#include <cstdlib>

#include "cli_checks.h"
#include "commands.h"
#include "terralod/build/build_stages.h"
#include "terralod/core/batch_memory.h"
#include "terralod/core/parallel.h"
#include "terralod/raster/dem_reader.h"

namespace terralod::cli {

void addBuildStageCommand(CLI::App& root, Runner& run) {
  auto* cmd = root.add_subcommand(
      "build-stage",
      "Run one task of a staged build (what `build --scheduler` submits as jobs; see `build "
      "--scheduler none` for the order)");
  auto stage = std::make_shared<std::string>();
  auto work = std::make_shared<std::string>();
  auto task = std::make_shared<int>(0);
  auto threads = std::make_shared<unsigned>(0);
  cmd->add_option("STAGE", *stage, "pass1, reduce, pass2, coarse or assemble")
      ->required()
      ->check(CLI::IsMember({"pass1", "reduce", "pass2", "coarse", "assemble"}));
  cmd->add_option("WORK", *work, "The build's work directory (holding plan.json)")->required();
  cmd->add_option("--task", *task, "Block job of pass1 and pass2 (0 .. jobs-1)")
      ->check(wholeNumber<int>());
  cmd->add_option("--threads", *threads,
                  "Worker threads (default: the CPUs Slurm allocated, $SLURM_CPUS_PER_TASK or "
                  "$SLURM_CPUS_ON_NODE, else all cores)")
      ->check(wholeNumber<unsigned>(1));
  cmd->footer(
      "Exit status: 0 done, 1 failed (one error line; also in WORK/status), 3 reduce found the "
      "height range estimate wrong and updated the plan (run pass1 and reduce again), 4 the stage "
      "before has not finished (nothing done; run it again later).\n");
  cmd->callback([&run, stage, work, task, threads] {
    run = [stage, work, task, threads] {
      keepFreedMemoryForReuse();
      // A job reads its blocks' windows one at a time, in order: GDAL's cache need hold only
      // a few rows of the raster's tiles. (64 MB, the default elsewhere, was an eighth of a
      // pass-2 job's peak at 16385², and no faster: with 16 MB the job took 0.96x the wall.)
      setGdalCacheBytes(uint64_t{16} << 20);
      unsigned n = *threads;
      if (n == 0) {
        // The CPUs Slurm gave the job (one unless asked), not the node's.
        const char* cpus = std::getenv("SLURM_CPUS_PER_TASK");
        if (!cpus) cpus = std::getenv("SLURM_CPUS_ON_NODE");
        n = cpus ? unsigned(std::max(1, std::atoi(cpus))) : hardwareThreads();
      }
      NullProgress progress;
      auto end = runStageTask(*work, *parseStageName(*stage), *task, n, progress);
      if (!end) return fail(end.error().message);
      if (*end == TaskEnd::kNotReady) {
        fail(*work + ": the stage before " + *stage + " has not finished");
        return 4;
      }
      return *end == TaskEnd::kReplanned ? 3 : 0;
    };
  });
}

}  // namespace terralod::cli
