// A build as explicit stages over a work directory (`build --scheduler local|none`,
// `build-stage`), without a scheduler: the same bytes as the local build, whatever the number
// of jobs, including when the plan's height estimate is wrong and pass 1 runs again; damaged
// stage files and foreign work directories get one error line and no output.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "cli_runner.h"
#include "temp_dir.h"

namespace terralod::test {
namespace {

namespace fs = std::filesystem;

class StagedBuild : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    sDir = new TempDir;
    const RunResult synth =
        runTerralod({"synth", "--size", "1025", "--spacing", "5", "--seed", "21", "-o", dem()});
    ASSERT_EQ(synth.exitCode, 0) << synth.err;
  }
  static void TearDownTestSuite() {
    delete sDir;
    sDir = nullptr;
  }
  static std::string dem() { return sDir->file("dem.tif"); }
  static std::string file(const std::string& name) { return sDir->file(name); }
  static TempDir* sDir;
};
TempDir* StagedBuild::sDir = nullptr;

TEST_F(StagedBuild, LocalStagesMatchTheLocalBuild) {
  // 64 blocks of 128 cells in 5 jobs, with textures (the range read whole, as the local build
  // does for a raster this small; shared, and one per chunk: pass 1 makes them, and the
  // chunks' own reach assemble in step with pass 2's chunks) and without (streamed: the range
  // estimated, as the local build's --memory-mb makes it stream), with RTIN and greedy meshes.
  // Greedy meshes too, streamed: each chunk's mesh depends on its parent's, kept per block.
  for (const std::vector<std::string>& options :
       {std::vector<std::string>{}, std::vector<std::string>{"--texture-per-chunk"},
        std::vector<std::string>{"--no-texture", "--memory-mb", "2"},
        std::vector<std::string>{"--no-texture", "--memory-mb", "2", "--mesher", "greedy"}}) {
    std::vector<std::string> local = {"build", dem(), "--block-cells",
                                      "128",   "-o",  file("local.tlod")};
    local.insert(local.end(), options.begin(), options.end());
    ASSERT_EQ(runTerralod(local).exitCode, 0);
    std::vector<std::string> staged = {
        "build",       dem(),   "--block-cells", "128",        "-o",     file("staged.tlod"),
        "--scheduler", "local", "--work-dir",    file("work"), "--jobs", "5"};
    staged.insert(staged.end(), options.begin(), options.end());
    const RunResult r = runTerralod(staged);
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_TRUE(has(r.out, "staged: local")) << r.out;
    EXPECT_EQ(readWholeFile(file("staged.tlod")), readWholeFile(file("local.tlod")));
    EXPECT_FALSE(fs::exists(file("work"))) << "the work directory is removed";
  }
}

// What another scheduler would run, by hand: `build --scheduler none` plans and prints the
// commands; the plan's height range is made too narrow, as a bad estimate would be; the reduce
// says so (status 3) and corrects the plan to the data's own range; pass 1 again; the result is
// what a local build that knows the range (reading the raster whole) makes.
TEST_F(StagedBuild, StageCommandsRecoverFromAWrongHeightEstimate) {
  const std::string work = file("manual");
  ASSERT_EQ(runTerralod({"build", dem(), "--no-texture", "-o", file("whole.tlod")}).exitCode, 0);
  const RunResult planned =
      runTerralod({"build", dem(), "--no-texture", "--memory-mb", "2", "-o", file("manual.tlod"),
                   "--scheduler", "none", "--work-dir", work, "--jobs", "3"});
  ASSERT_EQ(planned.exitCode, 0) << planned.err;
  EXPECT_TRUE(has(planned.out, "build-stage pass1 " + work + " --task T")) << planned.out;
  // The stages that read no raster are given to the program without GDAL beside terralod.
  EXPECT_TRUE(has(planned.out, "terralod-stage assemble " + work)) << planned.out;
  EXPECT_FALSE(fs::exists(file("manual.tlod")));

  nlohmann::json plan = nlohmann::json::parse(readWholeFile(work + "/plan.json"));
  ASSERT_FALSE(plan.at("exact_range").get<bool>());
  EXPECT_EQ(plan.at("jobs").get<int>(), 3);
  const double lo = plan.at("height_range")[0].get<double>();
  plan["height_range"] = {lo, lo + 1.0};
  std::ofstream(work + "/plan.json") << plan.dump();

  auto stage = [&](const std::string& name, int task = 0) {
    return runTerralod({"build-stage", name, work, "--task", std::to_string(task)});
  };
  // A stage started before the one it needs (as Slurm does when a job it waited for is
  // cancelled while pending) does nothing and records nothing.
  const RunResult early = stage("reduce");
  EXPECT_EQ(early.exitCode, 4) << early.err;
  EXPECT_TRUE(has(early.err, "the stage before reduce has not finished")) << early.err;
  EXPECT_FALSE(fs::exists(work + "/status/reduce-0.err"));
  EXPECT_FALSE(fs::exists(work + "/reduce/coarse.points"));
  for (int pass = 0; pass < 2; ++pass) {
    for (int t = 0; t < 3; ++t) ASSERT_EQ(stage("pass1", t).exitCode, 0) << pass << " " << t;
    const RunResult reduce = stage("reduce");
    ASSERT_EQ(reduce.exitCode, pass == 0 ? 3 : 0) << reduce.err;
    EXPECT_TRUE(fs::exists(work + "/status/reduce-0." + (pass == 0 ? "replan" : "ok")));
  }
  EXPECT_EQ(nlohmann::json::parse(readWholeFile(work + "/plan.json")).at("attempt").get<int>(), 1);
  for (int t = 0; t < 3; ++t) ASSERT_EQ(stage("pass2", t).exitCode, 0);
  ASSERT_EQ(stage("coarse").exitCode, 0);
  ASSERT_EQ(stage("assemble").exitCode, 0);
  EXPECT_EQ(readWholeFile(file("manual.tlod")), readWholeFile(file("whole.tlod")));

  // A task outside the plan is one error line.
  const RunResult outside = stage("pass2", 3);
  EXPECT_EQ(outside.exitCode, 1);
  EXPECT_EQ(outside.errLines().size(), 1u) << outside.err;
  EXPECT_TRUE(has(outside.err, "plan.json: has jobs 0..2, not 3")) << outside.err;
}

// terralod-stage runs reduce, pass 2 (of a build whose pass 1 kept the heights), coarse and
// assemble without GDAL: it links none, reads neither the DEM nor the draped image (both are
// gone after pass 1 here), and the tileset is the local build's. The stages that read a raster
// are refused with one line naming the command that runs them.
TEST_F(StagedBuild, StagesWithoutARasterRunWithoutGdal) {
  const std::string program = (fs::path(TERRALOD_CLI).parent_path() / "terralod-stage").string();
  ASSERT_TRUE(fs::exists(program)) << program;
  const RunResult needed = runProgram("readelf", {"-d", program});
  ASSERT_EQ(needed.exitCode, 0) << needed.err;
  EXPECT_TRUE(has(needed.out, "(NEEDED)")) << needed.out;
  EXPECT_FALSE(has(needed.out, "libgdal")) << needed.out;

  // The synth with the generated colour (its shade layer), and a void-free window of Zion with
  // its Landsat image draped (the image's texels per cell come from the plan).
  const std::string moved = file("moved.tif"), zion = file("zion.tif"),
                    image = file("zion-rgb.tif");
  fs::copy_file(dem(), moved, fs::copy_options::overwrite_existing);
  for (const auto& [from, to] : {std::pair{"zion_srtm3_utm12_30m.tif", zion},
                                 std::pair{"zion_landsat8_rgb_utm12_30m.tif", image}}) {
    const RunResult cut =
        runProgram("gdal_translate", {"-q", "-srcwin", "300", "500", "257", "257",
                                      std::string(TERRALOD_TEST_DATA) + "/" + from, to});
    ASSERT_EQ(cut.exitCode, 0) << cut.err;
  }
  for (const bool draped : {false, true}) {
    const std::string source = draped ? zion : moved;
    const std::string work = file(draped ? "slim-draped" : "slim");
    std::vector<std::string> options = {"--block-cells", "128"};
    if (draped) options.insert(options.end(), {"--texture", image});
    std::vector<std::string> local = {"build", source, "-o", file("slim-local.tlod")};
    local.insert(local.end(), options.begin(), options.end());
    ASSERT_EQ(runTerralod(local).exitCode, 0);
    std::vector<std::string> plan = {"build", source,       "-o", file("slim.tlod"), "--scheduler",
                                     "none",  "--work-dir", work, "--jobs",          "2"};
    plan.insert(plan.end(), options.begin(), options.end());
    const RunResult planned = runTerralod(plan);
    ASSERT_EQ(planned.exitCode, 0) << planned.err;
    const RunResult early = runProgram(program, {"pass1", work, "--task", "0"});
    EXPECT_EQ(early.exitCode, 1);
    ASSERT_EQ(early.errLines().size(), 1u) << early.err;
    EXPECT_TRUE(has(early.err, "terralod-stage: error: " + work +
                                   "/plan.json: pass1 reads the DEM (run it with `terralod "
                                   "build-stage pass1`)"))
        << early.err;
    for (int t = 0; t < 2; ++t)
      ASSERT_EQ(runTerralod({"build-stage", "pass1", work, "--task", std::to_string(t)}).exitCode,
                0);
    fs::rename(source, source + ".away");
    if (draped) fs::rename(image, image + ".away");
    auto stage = [&](const std::string& name, int task = 0) {
      return runProgram(program, {name, work, "--task", std::to_string(task)});
    };
    const RunResult reduce = stage("reduce");
    ASSERT_EQ(reduce.exitCode, 0) << reduce.err;
    for (int t = 0; t < 2; ++t) ASSERT_EQ(stage("pass2", t).exitCode, 0) << t;
    ASSERT_EQ(stage("coarse").exitCode, 0);
    const RunResult assemble = stage("assemble");
    ASSERT_EQ(assemble.exitCode, 0) << assemble.err;
    EXPECT_EQ(readWholeFile(file("slim.tlod")), readWholeFile(file("slim-local.tlod"))) << draped;
    fs::rename(source + ".away", source);
    if (draped) fs::rename(image + ".away", image);
  }

  // A greedy build's pass 2 reads the DEM.
  const std::string work = file("slim-greedy");
  ASSERT_EQ(
      runTerralod({"build", moved, "--no-texture", "--mesher", "greedy", "-o", file("greedy.tlod"),
                   "--scheduler", "none", "--work-dir", work, "--jobs", "1"})
          .exitCode,
      0);
  ASSERT_EQ(runTerralod({"build-stage", "pass1", work}).exitCode, 0);
  ASSERT_EQ(runProgram(program, {"reduce", work}).exitCode, 0);
  const RunResult greedy = runProgram(program, {"pass2", work});
  EXPECT_EQ(greedy.exitCode, 1);
  ASSERT_EQ(greedy.errLines().size(), 1u) << greedy.err;
  EXPECT_TRUE(has(greedy.err, "run it with `terralod build-stage pass2`")) << greedy.err;
  EXPECT_EQ(readWholeFile(work + "/status/pass2-0.err"),
            greedy.err.substr(greedy.err.find(work + "/plan.json")));
  ASSERT_EQ(runTerralod({"build-stage", "pass2", work}).exitCode, 0);
}

// The stages take the raster's size and spacing from the plan; one that reads the DEM refuses
// a DEM changed since the plan, in one line, and writes nothing.
TEST_F(StagedBuild, AStageRefusesADemChangedSinceThePlan) {
  const std::string changing = file("changing.tif"), work = file("changed");
  fs::copy_file(dem(), changing, fs::copy_options::overwrite_existing);
  ASSERT_EQ(runTerralod({"build", changing, "--no-texture", "-o", file("changed.tlod"),
                         "--scheduler", "none", "--work-dir", work, "--jobs", "2"})
                .exitCode,
            0);
  ASSERT_EQ(runTerralod({"synth", "--size", "513", "--spacing", "5", "--seed", "3", "-o", changing})
                .exitCode,
            0);
  const RunResult r = runTerralod({"build-stage", "pass1", work, "--task", "0"});
  EXPECT_EQ(r.exitCode, 1);
  ASSERT_EQ(r.errLines().size(), 1u) << r.err;
  EXPECT_TRUE(has(r.err, work + "/plan.json: was made for another raster than " + changing +
                             " (it has changed since the plan)"))
      << r.err;
  EXPECT_FALSE(fs::exists(work + "/pass1/job-0.grid"));
  EXPECT_TRUE(fs::exists(work + "/status/pass1-0.err"));
}

TEST_F(StagedBuild, ADamagedStageFileIsOneErrorAndNoOutput) {
  const std::string work = file("damaged");
  ASSERT_EQ(runTerralod({"build", dem(), "--no-texture", "-o", file("damaged.tlod"), "--scheduler",
                         "none", "--work-dir", work, "--jobs", "2"})
                .exitCode,
            0);
  for (int t = 0; t < 2; ++t)
    ASSERT_EQ(runTerralod({"build-stage", "pass1", work, "--task", std::to_string(t)}).exitCode, 0);
  const std::string victim = work + "/pass1/job-1.halo";
  const std::string bytes = readWholeFile(victim);
  ASSERT_GT(bytes.size(), 40u);
  std::ofstream(victim, std::ios::binary) << bytes.substr(0, bytes.size() - 7);
  const RunResult r = runTerralod({"build-stage", "reduce", work});
  EXPECT_EQ(r.exitCode, 1);
  ASSERT_EQ(r.errLines().size(), 1u) << r.err;
  EXPECT_TRUE(has(r.err, victim + ": damaged")) << r.err;
  EXPECT_EQ(readWholeFile(work + "/status/reduce-0.err"), r.err.substr(r.err.find(victim)));
  EXPECT_FALSE(fs::exists(file("damaged.tlod")));
  // The heights pass 1 kept for pass 2 (which reads no DEM in an RTIN build).
  std::ofstream(victim, std::ios::binary | std::ios::trunc) << bytes;
  ASSERT_EQ(runTerralod({"build-stage", "reduce", work}).exitCode, 0);
  const std::string kept = work + "/pass1/job-1.kept";
  const std::string keptBytes = readWholeFile(kept);
  ASSERT_GT(keptBytes.size(), 40u);
  std::ofstream(kept, std::ios::binary | std::ios::trunc)
      << keptBytes.substr(0, keptBytes.size() - 5);
  const RunResult pass2 = runTerralod({"build-stage", "pass2", work, "--task", "1"});
  EXPECT_EQ(pass2.exitCode, 1);
  ASSERT_EQ(pass2.errLines().size(), 1u) << pass2.err;
  EXPECT_TRUE(has(pass2.err, kept + ": damaged")) << pass2.err;
  EXPECT_FALSE(fs::exists(work + "/pass2/job-1.chunks"));
}

// The files the coarse job and assemble read a piece at a time (a job's textures, its
// chunks, frontier tiles) are checked against their CRC only at their end, after what they held has
// been written on: a byte changed in the middle must still give one line and no output.
TEST_F(StagedBuild, AStreamedStageFileDamagedInTheMiddleIsOneErrorAndNoOutput) {
  const std::string work = file("streamed");
  const std::string out = file("streamed.tlod");
  ASSERT_EQ(runTerralod({"build", dem(), "--block-cells", "128", "-o", out, "--scheduler", "none",
                         "--work-dir", work, "--jobs", "4"})
                .exitCode,
            0);
  auto stage = [&](const std::string& name, int task = 0) {
    return runTerralod({"build-stage", name, work, "--task", std::to_string(task)});
  };
  for (const char* name : {"pass1", "reduce", "pass2"})
    for (int t = 0; t < (std::string(name) == "reduce" ? 1 : 4); ++t)
      ASSERT_EQ(stage(name, t).exitCode, 0) << name << " " << t;
  // Flips one byte halfway through a file, keeping its size; returns the original bytes.
  auto damage = [](const std::string& path) {
    const std::string bytes = readWholeFile(path);
    std::string changed = bytes;
    changed[changed.size() / 2] = char(changed[changed.size() / 2] ^ 0x5a);
    std::ofstream(path, std::ios::binary | std::ios::trunc) << changed;
    return bytes;
  };
  auto expectOneDamagedLine = [&](const RunResult& r, const std::string& victim) {
    EXPECT_EQ(r.exitCode, 1);
    ASSERT_EQ(r.errLines().size(), 1u) << r.err;
    EXPECT_TRUE(has(r.err, victim + ": damaged")) << r.err;
  };
  // A job's frontier tiles, read a tile at a time as well (pass 1 makes the textures of an
  // RTIN build, from the windows it reads).
  const std::string tiles = work + "/pass1/job-1.tiles";
  const std::string tilesBefore = damage(tiles);
  expectOneDamagedLine(stage("coarse"), tiles);
  EXPECT_FALSE(fs::exists(work + "/coarse.chunks")) << "no coarse.chunks from damaged tiles";
  std::ofstream(tiles, std::ios::binary | std::ios::trunc) << tilesBefore;
  ASSERT_EQ(stage("coarse").exitCode, 0);
  // A job's textures, which assemble copies into the tileset as it reads them.
  const std::string textures = work + "/pass1/job-1.textures";
  const std::string original = damage(textures);
  expectOneDamagedLine(stage("assemble"), textures);
  EXPECT_FALSE(fs::exists(out)) << "no tileset from damaged textures";
  std::ofstream(textures, std::ios::binary | std::ios::trunc) << original;
  // The textures of the chunks below a job's blocks, read in step with its chunk file.
  const std::string chunkTextures = work + "/pass1/job-3.chunk-textures";
  const std::string chunkTexturesBefore = damage(chunkTextures);
  expectOneDamagedLine(stage("assemble"), chunkTextures);
  EXPECT_FALSE(fs::exists(out)) << "no tileset from damaged chunk textures";
  std::ofstream(chunkTextures, std::ios::binary | std::ios::trunc) << chunkTexturesBefore;
  const std::string chunks = work + "/pass2/job-2.chunks";
  damage(chunks);
  expectOneDamagedLine(stage("assemble"), chunks);
  EXPECT_FALSE(fs::exists(out)) << "no tileset from damaged input";
}

TEST_F(StagedBuild, NeverClearsAWorkDirectoryHoldingOtherFiles) {
  const std::string work = file("precious");
  fs::create_directories(work);
  std::ofstream(work + "/notes.txt") << "keep me";
  const RunResult r = runTerralod(
      {"build", dem(), "-o", file("p.tlod"), "--scheduler", "local", "--work-dir", work});
  EXPECT_EQ(r.exitCode, 1);
  EXPECT_EQ(r.errLines().size(), 1u) << r.err;
  EXPECT_TRUE(has(r.err, "holds files other than a staged build's")) << r.err;
  EXPECT_EQ(readWholeFile(work + "/notes.txt"), "keep me");
  EXPECT_FALSE(fs::exists(file("p.tlod")));
  // Options that only make sense together.
  EXPECT_TRUE(has(runTerralod({"build", dem(), "-o", file("p.tlod"), "--jobs", "4"}).err,
                  "--jobs applies to staged builds"));
  EXPECT_TRUE(has(runTerralod({"build", dem(), "-o", file("p.tlod"), "--scheduler", "local"}).err,
                  "--scheduler and --work-dir go together"));
}

}  // namespace
}  // namespace terralod::test
