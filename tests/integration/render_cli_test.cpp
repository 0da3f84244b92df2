// `terralod render` end to end: one view to a PNG, and a flight to frames plus a contact sheet.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <set>

#include "cli_runner.h"
#include "terralod/render/image.h"

namespace terralod::test {
namespace {

namespace fs = std::filesystem;

class RenderCli : public ::testing::Test {
 protected:
  void SetUp() override {
    const RunResult built =
        runTerralod({"build", testData("crater_lake_0513.bt"), "-o", mDir.file("c.tlod")});
    ASSERT_EQ(built.exitCode, 0) << built.err;
  }
  static size_t distinctColours(const Image& image) {
    std::set<uint32_t> colours;
    for (size_t i = 0; i < image.rgba.size(); i += 4)
      colours.insert(uint32_t(image.rgba[i]) << 16 | uint32_t(image.rgba[i + 1]) << 8 |
                     image.rgba[i + 2]);
    return colours.size();
  }
  TempDir mDir;
};

TEST_F(RenderCli, OneViewBecomesAPngOfTerrain) {
  const RunResult r = runTerralod({"render", mDir.file("c.tlod"), "-o", mDir.file("v.png"),
                                   "--size", "200x150", "--eye", "5500,2500,3000", "--target",
                                   "8800,7500,1900", "--wireframe", "--color-by", "morph"});
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_NE(r.out.find("draw calls"), std::string::npos) << r.out;
  auto image = readPng(mDir.file("v.png"));
  ASSERT_TRUE(image.ok()) << image.error().message;
  EXPECT_EQ(image->width, 200);
  EXPECT_EQ(image->height, 150);
  EXPECT_GT(distinctColours(*image), 50u) << "a blank or single-colour image";
}

// A view whose chunks do not fit the budget is drawn coarser than τ allows, and says so.
TEST_F(RenderCli, AViewThatDoesNotFitTheBudgetSaysSo) {
  auto render = [&](const std::string& cacheMB) {
    return runTerralod({"render", mDir.file("c.tlod"), "-o", mDir.file("b.png"), "--size",
                        "640x480", "--eye", "6500,4500,2300", "--target", "8800,7500,1900", "--tau",
                        "0.5", "--cache-mb", cacheMB});
  };
  const RunResult tight = render("0.5"), roomy = render("512");
  ASSERT_EQ(tight.exitCode, 0) << tight.err;
  ASSERT_EQ(roomy.exitCode, 0) << roomy.err;
  const std::string warning = "chunks drawn coarser than --tau allows";
  EXPECT_NE(tight.err.find(warning), std::string::npos) << tight.err;
  EXPECT_NE(tight.err.find("0.5 MB budget"), std::string::npos) << tight.err;
  EXPECT_EQ(roomy.err.find(warning), std::string::npos) << roomy.err;
}

// The name says the format: .jpg and .jpeg (any case) are JPEG, not PNG bytes under a JPEG name.
TEST_F(RenderCli, JpegNamesGetJpegBytes) {
  for (const char* name : {"v.jpg", "v.JPEG"}) {
    const RunResult r =
        runTerralod({"render", mDir.file("c.tlod"), "-o", mDir.file(name), "--size", "160x120"});
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const std::string bytes = readWholeFile(mDir.file(name));
    ASSERT_GT(bytes.size(), 1000u) << name;
    EXPECT_EQ(uint8_t(bytes[0]), 0xFF) << name;
    EXPECT_EQ(uint8_t(bytes[1]), 0xD8) << name;
    EXPECT_EQ(uint8_t(bytes[2]), 0xFF) << name;
    EXPECT_EQ(uint8_t(bytes[bytes.size() - 2]), 0xFF) << name;  // end of image marker
    EXPECT_EQ(uint8_t(bytes[bytes.size() - 1]), 0xD9) << name;
  }
  EXPECT_TRUE(readPng(mDir.file("v.jpg")).ok() == false) << "PNG bytes in a .jpg";
}

// Other names are refused with one line naming the file, before the tileset is even opened
// (here it does not exist), and nothing is written.
TEST_F(RenderCli, OtherImageNamesAreRefusedBeforeRendering) {
  for (const std::string name : {"v.bmp", "v.tif", "v"}) {
    const RunResult r = runTerralod(
        {"render", mDir.file("missing.tlod"), "-o", mDir.file(name), "--size", "64x48"});
    EXPECT_EQ(r.exitCode, 1) << name;
    const std::string expected = "terralod: error: " + mDir.file(name) + ": " +
                                 (name == "v" ? std::string("no image type in the name")
                                              : "cannot write " + name.substr(1) + " images") +
                                 ": name it .png, .jpg or .jpeg\n";
    EXPECT_EQ(r.err, expected);
    EXPECT_FALSE(fs::exists(mDir.file(name)));
  }
}

TEST_F(RenderCli, ChunkBoxesOutlineTheDrawnChunksInTheirLevelsColours) {
  auto render = [&](const std::string& out, std::vector<std::string> extra) {
    std::vector<std::string> args = {"render",   mDir.file("c.tlod"), "-o",    out,
                                     "--size",   "240x180",           "--eye", "5500,2500,3000",
                                     "--target", "8800,7500,1900"};
    args.insert(args.end(), extra.begin(), extra.end());
    const RunResult r = runTerralod(args);
    EXPECT_EQ(r.exitCode, 0) << r.err;
    return readPng(out).value();
  };
  const Image plain = render(mDir.file("plain.png"), {});
  const Image boxes = render(mDir.file("boxes.png"), {"--chunk-boxes"});
  // Lines: a few percent of the pixels change, and most of those take a level's colour.
  size_t changed = 0, palette = 0;
  const std::set<uint32_t> levelColours = {0xE6403D, 0xF29926, 0xE6D933, 0x59BF40,
                                           0x33B3BF, 0x4066E6, 0x9959D9, 0xD966A6};
  for (int y = 0; y < plain.height; ++y)
    for (int x = 0; x < plain.width; ++x) {
      const auto a = plain.pixel(x, y), b = boxes.pixel(x, y);
      if (a == b) continue;
      ++changed;
      palette += levelColours.count(uint32_t(b[0]) << 16 | uint32_t(b[1]) << 8 | b[2]);
    }
  const size_t pixels = size_t(plain.width) * size_t(plain.height);
  EXPECT_GT(changed, pixels / 500);
  EXPECT_LT(changed, pixels / 5);
  EXPECT_GT(palette, changed / 2);
}

TEST_F(RenderCli, FlightWritesEveryFrameAndAContactSheet) {
  std::ofstream(mDir.file("f.json")) << R"({"fov_deg": 50, "size": [96, 72], "frames": 7,
    "keyframes": [{"eye": [2000, 1000, 3500], "target": [6000, 7000, 1800]},
                  {"eye": [5000, 2000, 3000], "target": [8800, 7500, 1900]},
                  {"eye": [8000, 2500, 3200], "target": [9000, 8000, 1900]}]})";
  fs::create_directory(mDir.file("frames"));
  const RunResult r = runTerralod({"render", mDir.file("c.tlod"), "--flight", mDir.file("f.json"),
                                   "--frames-dir", mDir.file("frames")});
  ASSERT_EQ(r.exitCode, 0) << r.err;
  for (int i = 0; i < 7; ++i) {
    char name[32];
    std::snprintf(name, sizeof name, "frame_%05d.png", i);
    auto frame = readPng(mDir.file("frames/" + std::string(name)));
    ASSERT_TRUE(frame.ok()) << name;
    EXPECT_EQ(frame->width, 96);
  }
  EXPECT_FALSE(fs::exists(mDir.file("frames/frame_00007.png")));
  auto sheet = readPng(mDir.file("frames/contact_sheet.png"));
  ASSERT_TRUE(sheet.ok());
  EXPECT_GT(sheet->width, 6 * 96);  // six 256-pixel thumbnails across
}

TEST_F(RenderCli, EveryKthFrameKeepsItsFlightNumber) {
  fs::create_directory(mDir.file("some"));
  const RunResult r =
      runTerralod({"render", mDir.file("c.tlod"), "--auto-flight", "--frames", "7", "--every", "3",
                   "--size", "64x48", "--frames-dir", mDir.file("some")});
  ASSERT_EQ(r.exitCode, 0) << r.err;
  for (int i = 0; i < 7; ++i) {
    char name[32];
    std::snprintf(name, sizeof name, "some/frame_%05d.png", i);
    EXPECT_EQ(fs::exists(mDir.file(name)), i % 3 == 0) << name;
  }
  EXPECT_NE(r.out.find("wrote 3 frames"), std::string::npos) << r.out;
}

TEST_F(RenderCli, AutoFlightFliesTheFirstFrames) {
  fs::create_directory(mDir.file("auto"));
  const RunResult r = runTerralod({"render", mDir.file("c.tlod"), "--auto-flight", "--frames", "3",
                                   "--size", "64x48", "--frames-dir", mDir.file("auto")});
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_TRUE(fs::exists(mDir.file("auto/frame_00002.png")));
  EXPECT_FALSE(fs::exists(mDir.file("auto/frame_00003.png")));
}

}  // namespace
}  // namespace terralod::test
