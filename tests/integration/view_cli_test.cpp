// `terralod view` in a real window under a virtual X server: it plays a flight, saves the last
// frame, and that frame is the headless renderer's image of the same view — from a file, and
// streamed from a web server.

#include <gtest/gtest.h>

#include <fstream>
#include <set>

#include "cli_runner.h"
#include "image_compare.h"
#include "nginx_server.h"

namespace terralod::test {
namespace {

// Plays a short flight over `tileset` (a path or URL) in the viewer, saves its last frame, and
// checks it shows the terrain as the headless renderer draws the same view from `file`.
void expectViewerMatchesHeadless(const TempDir& dir, const std::string& tileset,
                                 const std::string& file) {
  std::ofstream(dir.file("f.json")) << R"({"fov_deg": 60, "size": [320, 240], "frames": 20,
    "keyframes": [{"eye": [5000, 1000, 3500], "target": [8800, 7500, 1900]},
                  {"eye": [5500, 2500, 3000], "target": [8800, 7500, 1900]}]})";
  // xvfb-run gets its own range of display numbers, so it never races the window test.
  const RunResult viewed =
      runProgram(TERRALOD_XVFB_RUN, {"-a", "-n", "250", "-s", "-screen 0 1280x1024x24 -noreset",
                                     TERRALOD_CLI, "view", tileset, "--play", dir.file("f.json"),
                                     "--screenshot", dir.file("shot.png"), "--exit-after-play"});
  ASSERT_EQ(viewed.exitCode, 0) << viewed.out << viewed.err;
  const RunResult rendered =
      runTerralod({"render", file, "-o", dir.file("headless.png"), "--eye", "5500,2500,3000",
                   "--target", "8800,7500,1900", "--size", "320x240"});
  ASSERT_EQ(rendered.exitCode, 0) << rendered.err;

  auto shot = readPng(dir.file("shot.png"));
  ASSERT_TRUE(shot.ok()) << shot.error().message;
  std::set<uint32_t> colours;
  for (size_t i = 0; i < shot->rgba.size(); i += 4)
    colours.insert(uint32_t(shot->rgba[i]) << 16 | uint32_t(shot->rgba[i + 1]) << 8 |
                   shot->rgba[i + 2]);
  EXPECT_GT(colours.size(), 50u) << "blank or single-colour screenshot";
  const Image headless = readPng(dir.file("headless.png")).value();
  // Window and headless contexts are different drivers' paths: allow a little.
  const auto c = compareImages(*shot, headless, ImageTolerance{4, 0.01});
  EXPECT_TRUE(c.matches) << "mean abs error " << c.meanAbsoluteError << ", differing "
                         << c.differingFraction << " " << c.message;
}

TEST(ViewCli, PlaysAFlightUnderXvfbAndMatchesTheHeadlessRender) {
  TempDir dir;
  ASSERT_EQ(
      runTerralod({"build", testData("crater_lake_0513.bt"), "-o", dir.file("c.tlod")}).exitCode,
      0);
  expectViewerMatchesHeadless(dir, dir.file("c.tlod"), dir.file("c.tlod"));
}

TEST(ViewCli, StreamsATilesetFromAWebServer) {
  TempDir dir, www;
  ASSERT_EQ(
      runTerralod({"build", testData("crater_lake_0513.bt"), "-o", www.file("c.tlod")}).exitCode,
      0);
  NginxServer server(www.path());
  ASSERT_TRUE(server.running()) << server.error();
  expectViewerMatchesHeadless(dir, server.url("c.tlod"), www.file("c.tlod"));
}

// A screenshot name the viewer cannot write is refused at once, before any window opens.
TEST(ViewCli, RefusesAScreenshotNameItCannotWrite) {
  TempDir dir;
  const RunResult r = runTerralod({"view", dir.file("missing.tlod"), "--screenshot",
                                   dir.file("shot.bmp"), "--exit-after-play"});
  EXPECT_EQ(r.exitCode, 1);
  EXPECT_EQ(r.err, "terralod: error: " + dir.file("shot.bmp") +
                       ": cannot write .bmp images: name it .png, .jpg or .jpeg\n");
}

}  // namespace
}  // namespace terralod::test

namespace terralod::test {
namespace {

// The brush, scripted: strokes applied while the flight plays are regenerated on a worker and
// swapped into the drawn tileset; the last frame (held until they are drawn) shows what the
// tileset written back at exit (--save-edits) draws headless.
TEST(ViewCli, ScriptedStrokesAreDrawnAndWrittenBack) {
  TempDir dir;
  const std::string dem = testData("crater_lake_0513.bt");
  ASSERT_EQ(runTerralod({"build", dem, "--kind", "vipm", "-o", dir.file("c.tlod")}).exitCode, 0);
  const std::string before = readWholeFile(dir.file("c.tlod"));
  std::ofstream(dir.file("f.json")) << R"({"fov_deg": 60, "size": [320, 240], "frames": 20,
    "keyframes": [{"eye": [5000, 1000, 3500], "target": [8800, 7500, 1900]},
                  {"eye": [5500, 2500, 3000], "target": [8800, 7500, 1900]}]})";
  // An island raised in the lake, and snow painted on it.
  std::ofstream(dir.file("s.json")) << R"({"edits": [
    {"brush": "raise", "center": [8000, 6500], "radius": 600, "amount": 150},
    {"brush": "paint", "center": [8800, 7500], "radius": 700, "material": 4}]})";
  const RunResult viewed = runProgram(
      TERRALOD_XVFB_RUN, {"-a", "-n", "260", "-s", "-screen 0 1280x1024x24 -noreset", TERRALOD_CLI,
                          "view", dir.file("c.tlod"), "--play", dir.file("f.json"), "--screenshot",
                          dir.file("shot.png"), "--exit-after-play", "--edit-script",
                          dir.file("s.json"), "--edit-source", dem, "--save-edits"});
  ASSERT_EQ(viewed.exitCode, 0) << viewed.out << viewed.err;
  EXPECT_NE(viewed.out.find("saved 2 strokes"), std::string::npos) << viewed.out;
  EXPECT_NE(readWholeFile(dir.file("c.tlod")), before);
  // (What it wrote is a build with the strokes, byte for byte: VipmChunkSet tests; such
  // tilesets verify: VipmEditCli.)

  const RunResult rendered =
      runTerralod({"render", dir.file("c.tlod"), "-o", dir.file("headless.png"), "--eye",
                   "5500,2500,3000", "--target", "8800,7500,1900", "--size", "320x240"});
  ASSERT_EQ(rendered.exitCode, 0) << rendered.err;
  const Image shot = readPng(dir.file("shot.png")).value();
  const Image headless = readPng(dir.file("headless.png")).value();
  const auto c = compareImages(shot, headless, ImageTolerance{4, 0.01});
  EXPECT_TRUE(c.matches) << "mean abs error " << c.meanAbsoluteError << ", differing "
                         << c.differingFraction << " " << c.message;
  // And the strokes show: the same view of the tileset before them differs.
  std::ofstream(dir.file("before.tlod"), std::ios::binary) << before;
  ASSERT_EQ(runTerralod({"render", dir.file("before.tlod"), "-o", dir.file("before.png"), "--eye",
                         "5500,2500,3000", "--target", "8800,7500,1900", "--size", "320x240"})
                .exitCode,
            0);
  const auto unchanged =
      compareImages(shot, readPng(dir.file("before.png")).value(), ImageTolerance{4, 0.01});
  EXPECT_FALSE(unchanged.matches) << "the strokes do not show";
}

}  // namespace
}  // namespace terralod::test
