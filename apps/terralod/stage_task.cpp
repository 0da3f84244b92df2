#include "stage_task.h"

#include <cstdio>
#include <cstdlib>

#include "cli_checks.h"
#include "terralod/core/batch_memory.h"
#include "terralod/core/parallel.h"

namespace terralod::cli {

void addStageTaskOptions(CLI::App& app, StageTaskArgs& args) {
  app.add_option("STAGE", args.stage, "pass1, reduce, pass2, coarse or assemble")
      ->required()
      ->check(CLI::IsMember({"pass1", "reduce", "pass2", "coarse", "assemble"}));
  app.add_option("WORK", args.work, "The build's work directory (holding plan.json)")->required();
  app.add_option("--task", args.task, "Block job of pass1 and pass2 (0 .. jobs-1)")
      ->check(wholeNumber<int>());
  app.add_option("--threads", args.threads,
                 "Worker threads (default: the CPUs Slurm allocated, $SLURM_CPUS_PER_TASK or "
                 "$SLURM_CPUS_ON_NODE, else all cores)")
      ->check(wholeNumber<unsigned>(1));
  app.footer(
      "Exit status: 0 done, 1 failed (one error line; also in WORK/status), 3 reduce found the "
      "height range estimate wrong and updated the plan (run pass1 and reduce again), 4 the stage "
      "before has not finished (nothing done; run it again later).\n");
}

int runStageTaskCommand(const StageTaskArgs& args, const char* program, StageTaskRunner run) {
  keepFreedMemoryForReuse();
  unsigned threads = args.threads;
  if (threads == 0) {
    // The CPUs Slurm gave the job (one unless asked), not the node's.
    const char* cpus = std::getenv("SLURM_CPUS_PER_TASK");
    if (!cpus) cpus = std::getenv("SLURM_CPUS_ON_NODE");
    threads = cpus ? unsigned(std::max(1, std::atoi(cpus))) : hardwareThreads();
  }
  NullProgress progress;
  auto end = run(args.work, *parseStageName(args.stage), args.task, threads, progress);
  if (!end) {
    std::fprintf(stderr, "%s: error: %s\n", program, end.error().message.c_str());
    return 1;
  }
  if (*end == TaskEnd::kNotReady) {
    std::fprintf(stderr, "%s: error: %s: the stage before %s has not finished\n", program,
                 args.work.c_str(), args.stage.c_str());
    return 4;
  }
  return *end == TaskEnd::kReplanned ? 3 : 0;
}

}  // namespace terralod::cli
