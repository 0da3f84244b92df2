// `terralod view` in a real window under a virtual X server: it plays a flight, saves the last
// frame, and that frame is the headless renderer's image of the same view.

#include <gtest/gtest.h>

#include <fstream>
#include <set>

#include "cli_runner.h"
#include "image_compare.h"

namespace terralod::test {
namespace {

TEST(ViewCli, PlaysAFlightUnderXvfbAndMatchesTheHeadlessRender) {
  TempDir dir;
  ASSERT_EQ(
      runTerralod({"build", testData("crater_lake_0513.bt"), "-o", dir.file("c.tlod")}).exitCode,
      0);
  std::ofstream(dir.file("f.json")) << R"({"fov_deg": 60, "size": [320, 240], "frames": 20,
    "keyframes": [{"eye": [5000, 1000, 3500], "target": [8800, 7500, 1900]},
                  {"eye": [5500, 2500, 3000], "target": [8800, 7500, 1900]}]})";
  // xvfb-run gets its own range of display numbers, so it never races the window test.
  const RunResult viewed = runProgram(
      TERRALOD_XVFB_RUN, {"-a", "-n", "250", "-s", "-screen 0 1280x1024x24 -noreset", TERRALOD_CLI,
                          "view", dir.file("c.tlod"), "--play", dir.file("f.json"), "--screenshot",
                          dir.file("shot.png"), "--exit-after-play"});
  ASSERT_EQ(viewed.exitCode, 0) << viewed.out << viewed.err;
  const RunResult rendered =
      runTerralod({"render", dir.file("c.tlod"), "-o", dir.file("headless.png"), "--eye",
                   "5500,2500,3000", "--target", "8800,7500,1900", "--size", "320x240"});
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

}  // namespace
}  // namespace terralod::test
