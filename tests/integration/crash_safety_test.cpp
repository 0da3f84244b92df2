// Crash safety of `terralod build`: killed with SIGKILL at random moments, it never leaves a
// file that opens as a tileset, and never touches an existing output before the new one is
// complete. The kill times are random (the seed is printed with any failure).

#include <gtest/gtest.h>
#include <signal.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <random>
#include <thread>

#include "cli_expectations.h"
#include "cli_runner.h"
#include "shared_directory.h"
#include "terralod/core/atomic_file.h"
#include "terralod/format/tileset_reader.h"

namespace terralod::test {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

constexpr int kKills = 4;

class CrashSafety : public ::testing::Test {
 protected:
  // Shared by the tests: a 2049² DEM (a build of about a second on two threads), its complete
  // tileset, and how long building it took.
  // Made once for every test process of this build of the CLI (the build time is kept beside).
  static void SetUpTestSuite() {
    const SharedDirectory dir =
        sharedDirectory("crash-synth", programStamp(TERRALOD_CLI), [](const std::string& d) {
          const std::string dem = d + "/dem.tif";
          if (RunResult r = runTerralod({"synth", "--size", "2049", "-o", dem}); r.exitCode != 0)
            return r.err;
          const auto start = Clock::now();
          const RunResult built =
              runTerralod({"build", dem, "-o", d + "/reference.tlod", "--threads", "2"});
          std::ofstream(d + "/build-seconds")
              << std::chrono::duration<double>(Clock::now() - start).count();
          return built.exitCode == 0 ? std::string() : built.err;
        });
    ASSERT_EQ(dir.error, "");
    sShared = new Shared{dir.file("dem.tif"), dir.file("reference.tlod"), 0.0};
    std::ifstream(dir.file("build-seconds")) >> sShared->buildSeconds;
    ASSERT_GT(sShared->buildSeconds, 0.0);
  }
  static void TearDownTestSuite() {
    delete sShared;
    sShared = nullptr;
  }
  void SetUp() override { ASSERT_TRUE(fs::exists(sShared->reference)); }
  static std::vector<std::string> buildArgs(const std::string& out) {
    return {"build", sShared->dem, "-o", out, "--threads", "2"};
  }
  // Starts a build of mOut and kills it after `seconds`; false if it had already exited. (A
  // build killed between its rename and its exit counts as killed, with a complete output.)
  bool buildAndKill(double seconds) {
    const pid_t pid = startProgram(TERRALOD_CLI, buildArgs(mOut.string()));
    std::this_thread::sleep_for(std::chrono::duration<double>(seconds));
    kill(pid, SIGKILL);
    int status = 0;
    waitpid(pid, &status, 0);
    return WIFSIGNALED(status);
  }
  // Nothing beside the output may open as a tileset; with unnamed temporary files (O_TMPFILE)
  // nothing may be there at all.
  void expectNoOtherTileset() const {
    std::vector<std::string> others;
    for (const auto& e : fs::directory_iterator(mOut.parent_path())) {
      if (e.path() == mOut) continue;
      others.push_back(e.path().filename().string());
      EXPECT_FALSE(TilesetReader::openFile(e.path().string()).ok())
          << e.path() << " opens as a tileset";
    }
    auto probe = AtomicFile::create((mOut.parent_path() / "probe").string());
    ASSERT_TRUE(probe.ok());
    if (probe->unnamed()) {
      EXPECT_TRUE(others.empty()) << "left behind: " << others.front();
    }
  }
  std::vector<double> killTimes() {
    std::uniform_real_distribution<double> when(0.0, 1.2 * sShared->buildSeconds);
    std::vector<double> times;
    for (int i = 0; i < kKills; ++i) times.push_back(when(mRandom));
    return times;
  }

  struct Shared {
    std::string dem, reference;
    double buildSeconds = 0;
  };
  static Shared* sShared;

  TempDir mDir;
  const fs::path mOut = mDir.path() / "terrain.tlod";
  const unsigned mSeed = std::random_device()();
  std::mt19937 mRandom{mSeed};
};
CrashSafety::Shared* CrashSafety::sShared = nullptr;

TEST_F(CrashSafety, AKilledBuildLeavesNoTileset) {
  SCOPED_TRACE("seed " + std::to_string(mSeed));
  const std::string reference = readWholeFile(sShared->reference);
  for (double t : killTimes()) {
    SCOPED_TRACE("killed after " + std::to_string(t) + " s");
    fs::remove(mOut);
    const bool killed = buildAndKill(t);
    // Either no output or the complete one.
    if (!killed || fs::exists(mOut)) {
      EXPECT_EQ(readWholeFile(mOut), reference) << "the output is not the complete tileset";
    }
    expectNoOtherTileset();
  }
}

TEST_F(CrashSafety, AKilledBuildNeverTouchesTheExistingOutput) {
  SCOPED_TRACE("seed " + std::to_string(mSeed));
  // The previous output: a different, complete tileset.
  const std::string previous = readWholeFile(testData("golden/v2/gully.tlod"));
  const std::string reference = readWholeFile(sShared->reference);
  int killed = 0;
  for (double t : killTimes()) {
    SCOPED_TRACE("killed after " + std::to_string(t) + " s");
    fs::copy_file(testData("golden/v2/gully.tlod"), mOut, fs::copy_options::overwrite_existing);
    const bool wasKilled = buildAndKill(t);
    killed += wasKilled;
    // Either the previous output, untouched, or the complete new one.
    const std::string now = readWholeFile(mOut);
    if (!wasKilled || now != previous) {
      EXPECT_EQ(now, reference) << "the output is neither the previous nor the complete tileset";
    }
    expectNoOtherTileset();
  }
  // And once more, killed early for certain (while reading the DEM).
  fs::copy_file(testData("golden/v2/gully.tlod"), mOut, fs::copy_options::overwrite_existing);
  ASSERT_TRUE(buildAndKill(0.05));
  EXPECT_EQ(readWholeFile(mOut), previous);
  expectNoOtherTileset();
  RecordProperty("killed_before_finishing", killed);
}

}  // namespace
}  // namespace terralod::test
