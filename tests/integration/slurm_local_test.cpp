// scripts/slurm-local.sh: a real single-node Slurm cluster (Debian's munge and slurm-wlm) that
// the tests start and stop. An array job and a job depending on it (afterok) run in order, a
// running job can be cancelled, and stop leaves no daemon and no directory behind.

#include <gtest/gtest.h>
#include <signal.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <thread>

#include "cli_runner.h"
#include "temp_dir.h"

namespace terralod::test {
namespace {

namespace fs = std::filesystem;

const std::string kScript = std::string(TERRALOD_SOURCE_DIR) + "/scripts/slurm-local.sh";

// `program args...` with SLURM_CONF set.
RunResult slurm(const std::string& conf, const std::string& program,
                const std::vector<std::string>& args) {
  return runProgram(program, args, {"SLURM_CONF=" + conf});
}

bool waitFor(const std::function<bool()>& done, double seconds) {
  for (int i = 0; i < int(seconds * 10); ++i) {
    if (done()) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  return done();
}

int pidIn(const fs::path& file) {
  std::ifstream in(file);
  int pid = 0;
  in >> pid;
  return pid;
}

TEST(SlurmLocal, RunsArrayJobsWithDependenciesAndStopsCleanly) {
  TempDir scratch;
  const std::string dir = scratch.file("cluster");
  // Stopped whatever happens below (a failed assertion returns early).
  struct StopAtEnd {
    std::string dir;
    ~StopAtEnd() { runProgram(kScript, {"stop", dir}); }
  } stopAtEnd{dir};
  const RunResult started = runProgram(kScript, {"start", dir});
  ASSERT_EQ(started.exitCode, 0) << started.out << started.err;
  const std::string conf = dir + "/slurm.conf";
  EXPECT_EQ(started.out, "export SLURM_CONF=" + conf + "\n");
  const int ctld = pidIn(dir + "/slurmctld.pid"), slurmd = pidIn(dir + "/slurmd.pid"),
            munged = pidIn(dir + "/munged.pid");
  ASSERT_GT(ctld, 0);
  ASSERT_GT(slurmd, 0);
  ASSERT_GT(munged, 0);
  // Starting twice is refused.
  EXPECT_NE(runProgram(kScript, {"start", dir}).exitCode, 0);

  // Four array tasks, then a job that runs only after all of them succeeded.
  const std::string out = scratch.file("out");
  fs::create_directories(out);
  const RunResult array = slurm(
      conf, "sbatch",
      {"--parsable", "--array=0-3", "-o", out + "/task_%a.txt", "--wrap",
       "echo $SLURM_ARRAY_TASK_ID; date +%s%N > " + out + "/end_$SLURM_ARRAY_TASK_ID; sleep 1"});
  ASSERT_EQ(array.exitCode, 0) << array.err;
  const std::string arrayId = array.out.substr(0, array.out.find_first_of(";\n"));
  const RunResult after = slurm(conf, "sbatch",
                                {"--parsable", "--dependency=afterok:" + arrayId, "-o",
                                 out + "/after.txt", "--wrap", "date +%s%N"});
  ASSERT_EQ(after.exitCode, 0) << after.err;
  ASSERT_TRUE(waitFor(
      [&] {
        std::error_code ec;
        const auto size = fs::file_size(out + "/after.txt", ec);
        return !ec && size > 0;
      },
      60))
      << slurm(conf, "squeue", {}).out;
  const auto number = [](const std::string& path) {
    std::ifstream in(path);
    long long v = 0;
    in >> v;
    return v;
  };
  const long long afterAt = number(out + "/after.txt");
  for (int task = 0; task < 4; ++task) {
    EXPECT_EQ(readWholeFile(out + "/task_" + std::to_string(task) + ".txt"),
              std::to_string(task) + "\n");
    EXPECT_LT(number(out + "/end_" + std::to_string(task)), afterAt) << task;
  }

  // A running job cancelled.
  const RunResult sleeper =
      slurm(conf, "sbatch", {"--parsable", "-o", out + "/sleeper.txt", "--wrap", "sleep 300"});
  ASSERT_EQ(sleeper.exitCode, 0);
  const std::string sleeperId = sleeper.out.substr(0, sleeper.out.find('\n'));
  ASSERT_TRUE(waitFor(
      [&] {
        return has(slurm(conf, "squeue", {"-h", "-j", sleeperId, "-o", "%T"}).out, "RUNNING");
      },
      30));
  EXPECT_EQ(slurm(conf, "scancel", {sleeperId}).exitCode, 0);
  EXPECT_TRUE(waitFor(
      [&] {
        return has(slurm(conf, "scontrol", {"show", "job", sleeperId}).out, "JobState=CANCELLED");
      },
      30));

  // Stopped: no daemon, no directory.
  const RunResult stopped = runProgram(kScript, {"stop", dir});
  EXPECT_EQ(stopped.exitCode, 0) << stopped.err;
  EXPECT_FALSE(fs::exists(dir));
  for (int pid : {ctld, slurmd, munged}) EXPECT_NE(kill(pid, 0), 0) << pid;
  EXPECT_NE(runProgram(kScript, {"status", dir}).exitCode, 0);
}

TEST(SlurmLocal, NeverClearsADirectoryItDidNotMake) {
  TempDir scratch;
  std::ofstream(scratch.file("precious.txt")) << "keep me";
  const RunResult r = runProgram(kScript, {"start", scratch.path().string()});
  EXPECT_NE(r.exitCode, 0);
  EXPECT_TRUE(has(r.err, "not empty")) << r.err;
  EXPECT_NE(runProgram(kScript, {"stop", scratch.path().string()}).exitCode, 0);
  EXPECT_TRUE(fs::exists(scratch.file("precious.txt")));
}

}  // namespace
}  // namespace terralod::test
