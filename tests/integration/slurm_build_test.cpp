// `terralod build --scheduler slurm` on a real single-node Slurm cluster (scripts/slurm-local.sh):
// a 2049² build (16 blocks) in 8 block jobs makes the local build's bytes, without textures, and
// with them while a job task is killed mid-way and another is cancelled while pending (both are
// submitted again); a stage that fails ends the build with its one error line and no tileset.

#include <gtest/gtest.h>
#include <signal.h>

#include <atomic>
#include <filesystem>
#include <thread>

#include "cli_runner.h"
#include "temp_dir.h"

namespace terralod::test {
namespace {

namespace fs = std::filesystem;

const std::string kClusterScript = std::string(TERRALOD_SOURCE_DIR) + "/scripts/slurm-local.sh";

// A process whose arguments include `args` in a row ({pid, the argument after them}), or
// {0, ""}. Read straight from /proc: a pass-2 task of two blocks lasts a few tens of
// milliseconds, less than starting pgrep takes on a loaded machine.
std::pair<pid_t, std::string> findProcess(const std::vector<std::string>& args) {
  std::string wanted;
  for (const std::string& a : args) wanted += a + '\0';
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator("/proc", ec)) {
    const std::string name = entry.path().filename().string();
    if (name.find_first_not_of("0123456789") != std::string::npos) continue;
    const std::string cmdline = readWholeFile(entry.path().string() + "/cmdline");
    const size_t at = cmdline.find(wanted);
    if (at == std::string::npos) continue;
    const size_t next = at + wanted.size();
    return {pid_t(std::stoi(name)), cmdline.substr(next, cmdline.find('\0', next) - next)};
  }
  return {0, ""};
}

class SlurmBuild : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    sDir = new TempDir;
    // Eight processors: the eight block jobs start at once rather than in waves (Slurm starts a
    // queued job about a second after the one before it ends).
    const RunResult started =
        runProgram(kClusterScript, {"start", cluster()}, {"SLURM_LOCAL_CPUS=8"});
    ASSERT_EQ(started.exitCode, 0) << started.out << started.err;
    const RunResult synth =
        runTerralod({"synth", "--size", "2049", "--spacing", "5", "--seed", "25", "-o", dem()});
    ASSERT_EQ(synth.exitCode, 0) << synth.err;
    ASSERT_EQ(runTerralod({"build", dem(), "-o", file("textured.tlod")}).exitCode, 0);
    // Streamed (the raster does not fit 8 MB): the plan starts from a height estimate.
    ASSERT_EQ(
        runTerralod({"build", dem(), "--no-texture", "--memory-mb", "8", "-o", file("plain.tlod")})
            .exitCode,
        0);
  }
  static void TearDownTestSuite() {
    runProgram(kClusterScript, {"stop", cluster()});
    delete sDir;
    sDir = nullptr;
  }
  static std::string cluster() { return sDir->file("cluster"); }
  static std::string dem() { return sDir->file("dem.tif"); }
  static std::string file(const std::string& name) { return sDir->file(name); }
  static std::vector<std::string> env() { return {"SLURM_CONF=" + cluster() + "/slurm.conf"}; }
  static RunResult slurm(const std::string& program, const std::vector<std::string>& args) {
    return runProgram(program, args, env());
  }
  static TempDir* sDir;
};
TempDir* SlurmBuild::sDir = nullptr;

// Eight jobs of two blocks each, streamed (the plan starts from a height estimate).
TEST_F(SlurmBuild, EightBlockJobsMakeTheLocalBuildsBytes) {
  const RunResult r =
      runTerralod({"build", dem(), "--no-texture", "--memory-mb", "8", "-o", file("cluster.tlod"),
                   "--scheduler", "slurm", "--work-dir", file("work"), "--jobs", "8"},
                  env());
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_TRUE(has(r.out, "staged: slurm")) << r.out;
  EXPECT_EQ(readWholeFile(file("cluster.tlod")), readWholeFile(file("plain.tlod")));
  EXPECT_FALSE(fs::exists(file("work"))) << "the work directory is removed";
  EXPECT_EQ(slurm("squeue", {"--me", "--noheader"}).out, "") << "no job left behind";
}

// With textures (the range read whole, as the local build does for this raster), in eight
// jobs, while a pass 2 task is killed mid-way and the coarse job is cancelled while it waits:
// both are submitted again and the bytes are still the local build's.
TEST_F(SlurmBuild, KilledAndCancelledTasksAreSubmittedAgain) {
  const std::string work = file("retried");
  RunResult result;
  std::atomic<bool> finished{false};
  std::thread driver([&] {
    result = runTerralod({"build", dem(), "-o", file("retried.tlod"), "--scheduler", "slurm",
                          "--work-dir", work, "--jobs", "8"},
                         env());
    finished = true;
  });
  // The coarse job, cancelled while it waits for pass 2.
  bool cancelled = false;
  for (int i = 0; i < 600 && !cancelled && !finished; ++i) {
    const std::string queue = slurm("squeue", {"--me", "--noheader", "--array",
                                               "--name=terralod-coarse", "--format=%i %T"})
                                  .out;
    if (has(queue, "PENDING"))
      cancelled = slurm("scancel", {queue.substr(0, queue.find(' '))}).exitCode == 0;
    else
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  // A pass 2 task's process, killed while it works: stopped first, and killed only if it has
  // not recorded its end (on a loaded machine a task found may finish before the
  // kill lands, and a finished task is rightly not run again).
  bool killed = false;
  for (int i = 0; i < 60000 && !killed && !finished; ++i) {
    // (terralod-stage runs it, or `terralod build-stage` without it.)
    const auto [pid, task] = findProcess({"pass2", work, "--task"});
    if (pid == 0 || task.empty()) {
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
      continue;
    }
    if (::kill(pid, SIGSTOP) != 0) continue;
    for (int k = 0;
         k < 200 &&
         readWholeFile("/proc/" + std::to_string(pid) + "/stat").find(") T ") == std::string::npos;
         ++k)
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    if (fs::exists(work + "/status/pass2-" + task + ".ok"))
      ::kill(pid, SIGCONT);
    else
      killed = ::kill(pid, SIGKILL) == 0;
  }
  driver.join();
  EXPECT_TRUE(cancelled);
  EXPECT_TRUE(killed);
  ASSERT_EQ(result.exitCode, 0) << result.err;
  EXPECT_TRUE(has(result.err, "coarse task 0 (job ")) << result.err;
  EXPECT_TRUE(has(result.err, "pass2 task ")) << result.err;
  EXPECT_TRUE(has(result.err, "ended without finishing; submitted again")) << result.err;
  EXPECT_EQ(readWholeFile(file("retried.tlod")), readWholeFile(file("textured.tlod")));
  EXPECT_FALSE(fs::exists(work));
}

TEST_F(SlurmBuild, AFailingStageLeavesNoTilesetAndOneError) {
  // Zion has voids; streamed (it does not fit 1 MB), only pass 1 sees them, and the reduce
  // says so.
  const std::string work = file("failing");
  const RunResult r =
      runTerralod({"build", testData("zion_srtm3_utm12_30m.tif"), "--memory-mb", "1", "-o",
                   file("failed.tlod"), "--scheduler", "slurm", "--work-dir", work, "--jobs", "4"},
                  env());
  EXPECT_EQ(r.exitCode, 1);
  const auto lines = r.errLines();
  ASSERT_EQ(lines.size(), 1u) << r.err;
  EXPECT_TRUE(has(lines[0], "zion_srtm3_utm12_30m.tif: has voids")) << lines[0];
  EXPECT_TRUE(has(lines[0], "(reduce job ")) << lines[0];
  EXPECT_FALSE(fs::exists(file("failed.tlod")));
  EXPECT_FALSE(fs::exists(work + "/plan.json")) << "stage files are removed";
  EXPECT_EQ(slurm("squeue", {"--me", "--noheader"}).out, "") << "the later stages are cancelled";
}

}  // namespace
}  // namespace terralod::test
